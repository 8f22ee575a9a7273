"""Clumps with the implicit scheme (physics.md P15a): a clump is one body of the implicit system,
its members' bridges act on it at the members' centres, and its inertia is the tensor
NewtonIntegrator turns it with.  A two-sphere clump lands tilted on a wet bed of four spheres on
a wet floor: implicit and explicit agree, the energy closes, and the implicit scheme keeps working
at steps where the explicit one cannot."""
import math

import pytest
from yade import O, utils
import yade.wrapper as yw
from yade.minieigenHP import Quaternion, Vector3

import viscbridge
from wetpairs import R, decay_time_wall, material

MU = 0.1
S_MIN = 1e-3 * R
T_END = 4e-3


def clump_on_a_bed(integration, dt, run=True):
    """Four spheres on a floor, 0.02 r apart, and above them a clump of two touching spheres
    tilted by 0.2 r in height, with a sideways velocity and spin, all wet (μ = 0.1 Pa·s,
    'slip', bridges form within 0.2 r)."""
    O.reset()
    mat = material()
    O.bodies.append(utils.wall(0, axis=2, material=mat))
    pitch = 2.02 * R
    O.bodies.append([utils.sphere((i * pitch, j * pitch, 1.001 * R), R, material=mat) for i in range(2) for j in range(2)])
    O.bodies.appendClumped([utils.sphere((0.3 * R, 0.3 * R, 3.1 * R), R, material=mat),
                            utils.sphere((1.7 * R, 1.8 * R, 3.3 * R), R, material=mat)])
    clump = O.bodies[-1]
    assert clump.isClump and clump.aspherical
    clump.state.vel = (0.02, 0, -0.05)
    clump.state.angVel = (0, 0, 20.0)
    O.engines = viscbridge.engines(timeStepper=False, guard=True, viscosity=MU, sMin=S_MIN, tangentialModel='slip',
                                   formationDistance=0.2 * R, minRadius=R, integration=integration)
    O.dt = dt
    O.trackEnergy = True
    if run:
        O.run(steps(dt), True)
    return clump


def steps(dt):
    return int(round(T_END / dt))


def clump_motion(clump):
    """The clump's displacement and its members' positions (lengths in r)."""
    members = [O.bodies[i].state.pos / R for i in sorted(clump.shape.members.keys())]
    return clump.state.pos / R, members


def bridges_on_members(clump):
    members = set(clump.shape.members.keys())
    return sum(1 for i in O.interactions if i.isReal and i.phys.bridge and {i.id1, i.id2} & members)


@pytest.fixture(scope='module')
def explicit_reference():
    t_v = decay_time_wall(MU, S_MIN)
    start = clump_on_a_bed('explicit', 0.05 * t_v, run=False)
    centre0, ori0 = Vector3(start.state.pos), Quaternion(start.state.ori)
    clump = clump_on_a_bed('explicit', 0.05 * t_v)
    centre, members = clump_motion(clump)
    assert bridges_on_members(clump) >= 2  # it landed: bridges to the bed from both members
    return centre0 / R, ori0, centre, members, clump.state.ori


def angle_between(q1, q2):
    return (q1.conjugate() * q2).toAngleAxis()[0]


def test_implicit_clump_follows_the_explicit_one(explicit_reference):
    """At the explicit run's step (0.05 t_v, where both schemes resolve the bridges) the members'
    positions agree within 1 % of the clump's travel, and the orientations within 1 % of its turn."""
    centre0, ori0, centre_e, members_e, ori_e = explicit_reference
    t_v = decay_time_wall(MU, S_MIN)
    clump = clump_on_a_bed('implicit', 0.05 * t_v)
    solver = next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver))
    assert solver.solves > 0 and solver.fallbacks == 0
    _, members_i = clump_motion(clump)
    travel = (centre_e - centre0).norm()
    assert travel > 0.2  # it fell onto the bed and was held there by the bridges
    for a, b in zip(members_i, members_e):
        assert (a - b).norm() <= 0.01 * travel, (a, b, travel)
    turn = angle_between(ori0, ori_e)
    assert turn > 0.02  # the spin turned it before the bridges stopped it
    assert angle_between(clump.state.ori, ori_e) <= 0.01 * turn


@pytest.mark.parametrize('dt_over_tv', [0.5, 20.0])
def test_implicit_clump_energy_closes(dt_over_tv):
    """The clump's initial kinetic energy plus gravity's work is the kinetic energy plus what the
    bridges and contacts dissipated, within 1 % of the energy put in."""
    t_v = decay_time_wall(MU, S_MIN)
    clump_on_a_bed('implicit', dt_over_tv * t_v, run=False)
    ke0 = utils.kineticEnergy()
    O.run(steps(dt_over_tv * t_v), True)
    E = dict(O.energy.items())
    assert E['viscDissipNormal'] > 0 and E['viscDissipTangential'] > 0 and E['gravWork'] < 0
    assert abs(O.energy.total() - ke0) <= 0.01 * (ke0 - E['gravWork']), E


def test_implicit_clump_at_a_step_the_explicit_scheme_cannot_take(explicit_reference, run_error):
    """At 20 t_v (explicit stops: the guard) the implicit clump still lands where the reference
    does, within 5 % of its travel (backward Euler's first-order error at this step)."""
    centre0, _, centre_e, members_e, _ = explicit_reference
    t_v = decay_time_wall(MU, S_MIN)
    clump_on_a_bed('explicit', 20 * t_v, run=False)
    assert 'ViscBridgeGuard stopped the run' in run_error(steps(20 * t_v))
    clump = clump_on_a_bed('implicit', 20 * t_v)
    _, members_i = clump_motion(clump)
    travel = (centre_e - centre0).norm()
    assert all(math.isfinite(c) for m in members_i for c in m)
    for a, b in zip(members_i, members_e):
        assert (a - b).norm() <= 0.05 * travel, (a, b, travel)


def test_a_spinning_clump_in_stiff_bridges_loses_its_energy_to_the_bridges():
    """A clump lying on a wet floor, both members 2 S_min above it, spun about a tilted axis, at the
    Hertz collision step with μ = 100 Pa·s (Δt·C/I ≫ 1): backward Euler damps the spin about the
    vertical and the sliding at once and leaves rolling about the clump's long axis (which the
    bridges do not resist: 'slip' has no rolling term); the kinetic energy never grows, and what it
    lost is what the bridges dissipated (1 %).  This needs the inertia tensor Newton turns the clump
    with: the principal moments taken in the global frame (ratio 3.7 here) break the balance."""
    from viscbridge import criteria
    from wetpairs import RHO
    mu, s_min = 100.0, 1e-3 * R
    mat = material()
    O.bodies.append(utils.wall(0, axis=2, material=mat))
    O.bodies.appendClumped([utils.sphere((0, 0, R + 2 * s_min), R, material=mat),
                            utils.sphere((1.4 * R, 1.4 * R, R + 2 * s_min), R, material=mat)])
    clump = O.bodies[-1]
    clump.state.angVel = (30.0, -10.0, 50.0)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), timeStepper=False, guard=False, viscosity=mu, sMin=s_min,
                                   tangentialModel='slip', formationDistance=0.2 * R, minRadius=R, integration='implicit')
    O.dt = 0.2 * criteria.rayleigh_time(R, RHO, 1e7, 0.3)
    assert O.dt / decay_time_wall(mu, s_min) > 1e3
    O.trackEnergy = True
    ke = [utils.kineticEnergy()]
    for _ in range(60):
        O.run(1, True)
        ke.append(utils.kineticEnergy())
    assert all(b <= a * (1 + 1e-6) for a, b in zip(ke, ke[1:])), ke
    assert abs(clump.state.angVel[2]) < 1e-6 * 50.0  # the spin about the vertical is gone
    long_axis = Vector3(1, 1, 0).normalized()
    assert clump.state.angVel.cross(long_axis).norm() < 1e-4 * clump.state.angVel.norm()  # rolling is left
    assert ke[-1] < 0.01 * ke[0]
    dissipated = sum(v for k, v in O.energy.items() if k.startswith('viscDissip'))
    assert dissipated == pytest.approx(ke[0] - ke[-1], rel=0.01)
