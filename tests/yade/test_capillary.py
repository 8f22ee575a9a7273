"""Capillary bridges (physics.md §8): the force agrees with YADE's own Willett law, a bridge of surface
tension alone holds a sphere under a ceiling and an agglomerate together, its energy is booked, and
the time step and the implicit scheme take it."""
import math
import random

import pytest
from yade import O, utils
import yade.wrapper as yw

import viscbridge
import viscbridge.scenes as scenes
from viscbridge import criteria
from wetpairs import R, RHO, material, sphere_mass

pytestmark = pytest.mark.slow  # settling runs and a scan trial

GAMMA = 0.072  # N/m, water


def capillary_pair(gap, model='willett', volume=None, theta=0.0):
    """Two equal spheres whose bridge formed at contact, now held at `gap` (fixed: the force is read)."""
    mat = material()
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat, fixed=True), utils.sphere((2 * R, 0, 0), R, material=mat, fixed=True)])
    kw = dict(bridgeVolume=volume) if volume else {}
    O.engines = viscbridge.engines(viscosity=0.0, capillaryModel=model, surfaceTension=GAMMA, contactAngle=theta, gravity=(0, 0, 0),
                                   timeStepper=False, guard=False, minRadius=R, formationDistance=1e-9, **kw)
    O.dt = 1e-8
    O.step()  # the bridge forms at contact
    O.bodies[1].state.pos = (2 * R + gap, 0, 0)
    O.step()
    return O.interactions[0, 1].phys


def yade_willett_force(gap, volume):
    """The same pair with YADE's Law2_ScGeom_ViscElCapPhys_Basic, CapillarType='Willett_analytic'."""
    O.reset()
    mat = O.materials.append(yw.ViscElCapMat(tc=1e-4, en=1.0, et=1.0, density=RHO, frictionAngle=0.5, Capillar=True, Vb=volume,
                                             gamma=GAMMA, theta=0, CapillarType='Willett_analytic'))
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat, fixed=True), utils.sphere((2 * R, 0, 0), R, material=mat, fixed=True)])
    O.engines = [yw.ForceResetter(), yw.InsertionSortCollider([yw.Bo1_Sphere_Aabb(aabbEnlargeFactor=1.5)]),
                 yw.InteractionLoop([yw.Ig2_Sphere_Sphere_ScGeom(interactionDetectionFactor=1.5)],
                                    [yw.Ip2_ViscElCapMat_ViscElCapMat_ViscElCapPhys()], [yw.Law2_ScGeom_ViscElCapPhys_Basic()]),
                 yw.NewtonIntegrator(gravity=(0, 0, 0))]
    O.dt = 1e-8
    O.step()
    O.bodies[1].state.pos = (2 * R + gap, 0, 0)
    O.step()
    return O.forces.f(0)[0]  # the pull on body 0, towards body 1 (+x)


def test_willett_agrees_with_yades_willett_analytic_over_the_whole_range():
    volume = 0.01 * 4 / 3 * math.pi * R ** 3
    s_rup = criteria.rupture_distance(volume)
    for f in (0.001, 0.01, 0.05, 0.1, 0.3, 0.6, 0.95):
        O.reset()
        ours = capillary_pair(f * s_rup, volume=volume).capillaryForce[0]
        theirs = yade_willett_force(f * s_rup, volume)
        assert theirs > 0 and ours == pytest.approx(theirs, rel=0.02), (f, ours, theirs)


def test_force_at_contact_is_two_pi_r_gamma_cos_theta():
    for theta in (0.0, 0.5):
        O.reset()
        ph = capillary_pair(0.0, theta=theta)
        assert ph.capillaryForce.norm() == pytest.approx(2 * math.pi * R * GAMMA * math.cos(theta), rel=1e-12)
        assert ph.bridge and ph.viscosity == 0 and ph.capillaryModel == 'willett' and ph.normalModel == 'none'


def test_rabinovich_force_against_gap_matches_the_formula():
    volume = 0.01 * 4 / 3 * math.pi * R ** 3
    for f in (0.01, 0.2, 0.8):
        O.reset()
        S = f * criteria.rupture_distance(volume)
        ph = capillary_pair(S, model='rabinovich', volume=volume)
        assert ph.capillaryForce.norm() == pytest.approx(criteria.capillary_force('rabinovich', R / 2, GAMMA, 0, volume, S), rel=1e-12)


def test_the_bridge_ruptures_at_lians_distance():
    volume = 0.01 * 4 / 3 * math.pi * R ** 3
    s_rup = criteria.rupture_distance(volume)
    ph = capillary_pair(0.99 * s_rup, volume=volume)
    assert ph.bridge and ph.capillaryForce.norm() > 0
    O.bodies[1].state.pos = (2 * R + 1.01 * s_rup, 0, 0)
    O.step()
    assert not O.interactions.has(0, 1) or not O.interactions[0, 1].isReal


def hanging_sphere(gamma):
    """A sphere touching a ceiling under gravity, wetted by a liquid of surface tension gamma."""
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, sense=-1, material=mat), utils.sphere((0, 0, -0.999 * R), R, material=mat)])
    O.engines = viscbridge.engines(viscosity=0.01, capillaryModel='willett', surfaceTension=gamma)
    O.dt = 1e-8
    O.run(1, True)
    O.stopAtTime = 0.4  # through the viscous film the fall starts slowly (R4-like, ~0.1 s at μ = 0.01)
    O.run(-1, True)
    O.stopAtTime = 0
    return O.bodies[1].state.pos[2]


@pytest.mark.parametrize('ratio,hangs', [(1.2, True), (0.8, False)])
def test_a_sphere_hangs_under_a_ceiling_while_its_weight_is_below_the_capillary_force(ratio, hangs):
    """Against a wall F(0) = 4πrγ (Derjaguin radius 2r): γ for F(0) = ratio × the weight."""
    gamma = ratio * sphere_mass() * 9.81 / (4 * math.pi * R)
    z = hanging_sphere(gamma)
    if hangs:
        assert z > -1.001 * R and O.interactions[0, 1].phys.bridge
    else:
        assert z < -3 * R  # fell away (the viscous bridge alone holds nothing at rest)
        assert not O.interactions.has(0, 1) or not O.interactions[0, 1].isReal


def slab(gamma, seed=1):
    """50 wet spheres stacked 5 × 2 × 5 (slightly jittered), dropped onto a wall at 0.5 m/s."""
    mat = material()
    O.bodies.append(utils.wall(0, axis=2, sense=1, material=mat))
    rng = random.Random(seed)
    ids = [O.bodies.append(utils.sphere((2 * R * i + rng.uniform(-1, 1) * 0.04 * R, 2 * R * j + rng.uniform(-1, 1) * 0.04 * R,
                                         3 * R + 2 * R * k * 0.9999), R, material=mat))
           for i in range(5) for j in range(2) for k in range(5)]
    for i in ids:
        O.bodies[i].state.vel = (0, 0, -0.5)
    O.engines = viscbridge.engines(viscosity=0.01, capillaryModel='willett', surfaceTension=gamma, formationDistance=0.01 * R)
    O.dt = 1e-7
    O.run(1, True)
    O.stopAtTime = 0.15
    O.run(-1, True)
    O.stopAtTime = 0
    pos = [O.bodies[i].state.pos for i in ids]
    return max(p[2] for p in pos) - min(p[2] for p in pos), max(p[0] for p in pos) - min(p[0] for p in pos)


def test_an_agglomerate_holds_together_with_surface_tension_and_breaks_up_without():
    height, spread = slab(GAMMA)
    assert height > 0.95 * 8 * R and spread < 1.3 * 8 * R  # still the 5-high slab it was
    O.reset()
    height, spread = slab(0.0)
    assert height < 0.5 * 8 * R and spread > 1.5 * 8 * R   # collapsed into a heap


def test_energy_closes_in_a_capillary_settling_run():
    s = scenes.settling(n=60, viscosity=0.01, capillaryModel='willett', surfaceTension=GAMMA, seed=2)
    assert s.run(duration=0.03) is None
    E = dict(O.energy.items())
    assert E.get('capillaryWork', 0) < 0  # the pull has done work on the particles
    scale = max(abs(v) for v in E.values())
    assert abs(O.energy.total()) <= 0.01 * scale, E


def test_energy_closes_when_a_bridge_is_pulled_apart_and_ruptures():
    """A wall pulls one sphere away from another: what the wall did is the kinetic energy, the
    viscous dissipation and the capillary work (the energy left in the liquid at rupture is booked)."""
    mat = material()
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((2 * R, 0, 0), R, material=mat, fixed=True)])
    O.bodies[0].state.blockedDOFs = 'xyzXYZ'  # held in place
    O.bodies[1].state.vel = (0.05, 0, 0)     # kinematic: pulls the bridge apart
    O.engines = viscbridge.engines(viscosity=0.01, capillaryModel='willett', surfaceTension=GAMMA, gravity=(0, 0, 0))
    O.trackEnergy = True
    O.dt = 1e-8
    O.run(1, True)
    start = O.energy.total()  # the pulling sphere's own kinetic energy, constant
    O.stopAtTime = 0.01
    O.run(-1, True)
    O.stopAtTime = 0
    assert not O.interactions.has(0, 1) or not O.interactions[0, 1].isReal  # ruptured
    E = dict(O.energy.items())
    # the liquid took U(0) = 0.1275 F(0) R (physics.md P21) from the wall: booked, not lost
    assert E['capillaryWork'] == pytest.approx(0.1275 * 2 * math.pi * R * GAMMA * R, rel=0.01)
    assert E['boundaryWork'] < 0
    assert abs(O.energy.total() - start) <= 0.01 * abs(E['boundaryWork']), E


def test_implicit_with_capillary_forces_is_stable_at_the_collision_step():
    s = scenes.settling(n=60, viscosity=100.0, capillaryModel='rabinovich', surfaceTension=GAMMA, integration='implicit', seed=3)
    why, _ = s.settle(0.06)
    assert why is None
    ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
    assert O.dt == pytest.approx(ts.dtCollision, rel=0.01)  # the collision step governs
    assert s.kinetic_energy() < s.released_energy()


def test_the_capillary_stiffness_enters_the_time_step():
    volume = 0.01 * 4 / 3 * math.pi * R ** 3
    ph = capillary_pair(0.01 * criteria.rupture_distance(volume), volume=volume)
    assert ph.capillaryStiffness == pytest.approx(criteria.capillary_max_stiffness('willett', R / 2, GAMMA, 0, volume,
                                                                                     criteria.rupture_distance(volume)), rel=1e-12)
    plan = criteria.critical_dt(R, RHO, 1e7, 0.3, 0.0, capillary_model='willett', surface_tension=GAMMA)
    spring = plan.bound('capillary_spring').value
    assert spring == pytest.approx(2 * math.sqrt(sphere_mass() / 2 / ph.capillaryStiffness), rel=1e-9)


def test_the_tools_accept_the_capillary_parameters():
    import viscbridge.scan as scan
    case = scan.normalize_case(dict(capillaryModel='rabinovich', surfaceTension=0.03))
    assert case['capillaryModel'] == 'rabinovich' and case['surfaceTension'] == 0.03
    with pytest.raises(ValueError, match='capillaryModel'):
        scan.normalize_case(dict(capillaryModel='lambert'))
    with pytest.raises(ValueError, match='surfaceTension'):
        viscbridge.engines(surfaceTension=-1.0)
    ip2 = next(e for e in viscbridge.engines(capillaryModel='willett', surfaceTension=0.05) if isinstance(e, yw.InteractionLoop)).physDispatcher.functors[0]
    assert (ip2.capillaryModel, ip2.surfaceTension) == ('willett', 0.05)


def test_the_scans_energy_verdict_counts_what_the_capillary_pull_puts_in(tmp_path):
    """A bed wetted with capillary bridges alone (μ = 0, γ = 0.072 N/m): the pull gives the spheres
    kinetic energy by itself, so the criterion counts it with the released potential energy — stable
    at the collision step and below, unstable far above (before, every Δt from 1e-6 s was
    'unstable', and a scan reported a critical step 250× too small)."""
    from viscbridge import scan
    case = scan.normalize_case(dict(n=40, steps=300, viscosity=0.0, capillaryModel='willett', surfaceTension=GAMMA))
    trial = scan._Trial(case, scan.dry_bed(case, str(tmp_path)))
    for dt in (1e-7, 1e-6, 8.65e-6):
        assert trial.unstable_at(dt) is None, dt
    assert trial.unstable_at(3e-4)


def test_a_capillary_settling_run_is_not_called_unstable():
    """The settling scene's own check, on a cloud landing with capillary bridges alone (implicit, μ = 0)."""
    s = scenes.settling(n=60, seed=2, cloudFraction=0.25, integration='implicit', viscosity=0.0, capillaryModel='willett',
                        surfaceTension=GAMMA)
    assert s.run(duration=0.02) is None
    assert s.bridges() > 20 and scenes.capillary_input() != 0  # net: pulls in, ruptures take U(S_f) back
