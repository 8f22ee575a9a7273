"""The implicit viscous scheme (physics.md §4, P15): backward Euler over the contact network by
ViscBridgeImplicitSolver.  The closed forms R1–R3 at Δt ≤ 0.01 t_v run for both schemes in
test_pair_trajectories.py; here: what the explicit scheme cannot do."""
import math
import random
import re

import pytest
from yade import O, utils
from yade.minieigenHP import Vector3
import yade.wrapper as yw

import viscbridge
from viscbridge import criteria
from wetpairs import (R, RHO, Recorder, crossing, decay_time_pair, decay_time_wall, gap_and_approach,
                      head_on_pair, material, sphere_mass)


def solver():
    return next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver))


def test_approach_stays_bounded_and_monotone_at_100_decay_times():
    """μ = 1 Pa·s, from 10 S_min at 1 m/s: it stops at S* = S0 e^(−w0/A) = 5.7 S_min.  At
    Δt = 100 t_v(S_min) the coefficient near S* makes Δt·C/m* ≈ 17: the explicit factor
    (1 − 17) would reverse and amplify the velocity every step; backward Euler divides by 1 + 17."""
    mu, s_min = 1.0, 1e-4 * R
    S0, w0 = 10 * s_min, 1.0
    head_on_pair(S0, w0, viscosity=mu, sMin=s_min, tangentialModel='none', integration='implicit')
    O.dt = 100 * decay_time_pair(mu, s_min)
    rec = Recorder(gap_and_approach)
    O.run(200, True)
    S = [s for s, _ in rec.rows]
    w = [v for _, v in rec.rows]
    noise = 1e-12 * w0  # once stopped, the velocity is round-off around 0
    assert all(b <= a + noise * O.dt for a, b in zip(S, S[1:])), 'the gap must not open again'
    assert all(v >= -noise for v in w), 'no rebound'
    assert all(b <= a + noise for a, b in zip(w, w[1:])), 'the approach speed only decreases'
    assert s_min < S[-1] < S0 and abs(w[-1]) < 1e-9 * w0  # bounded: it stops in the film
    S_star = S0 * math.exp(-w0 / 1.8)
    assert 0.5 * S_star < S[-1] < S_star * 1.05  # first order at this Δt: within a factor of S*


def test_R4_terminal_speed_at_100_decay_times():
    """Sphere settling onto a wall (physics.md R4): backward Euler gives the exact terminal speed
    S/τ_g at any Δt; here Δt = 100 t_v with t_v at S_min = 1e-5 r."""
    mu, g = 0.1, 9.81
    S0, S1, s_min = 1e-2 * R, 1e-3 * R, 1e-5 * R
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, R + S0), R, material=mat)])
    O.engines = viscbridge.engines(gravity=(0, 0, -g), timeStepper=False, guard=False, viscosity=mu, sMin=s_min,
                                   tangentialModel='none', formationDistance=2 * S0, integration='implicit')
    O.dt = 100 * decay_time_wall(mu, s_min)
    assert O.dt < 0.2 * criteria.rayleigh_time(R, RHO, 1e7, 0.3)  # still resolves a collision
    tau_g = 6 * math.pi * mu * R ** 2 / (sphere_mass() * g)
    ball = O.bodies[1].state
    samples = []
    while not samples or samples[-1][1] > S1:
        O.run(500, True)
        samples.append((O.time, ball.pos[2] - R, -ball.vel[2]))
    w = crossing([math.log(s) for _, s, _ in samples], [v for _, _, v in samples], math.log(S1))
    assert w == pytest.approx(S1 / tau_g, rel=0.01)
    t = crossing([math.log(s) for _, s, _ in samples], [t for t, _, _ in samples], math.log(S1))
    assert t == pytest.approx(tau_g * math.log(S0 / S1), rel=0.01)


# --- a dense wet packing at the collision step ---------------------------------------------------
def lattice(n_side=8, mu=1000.0, integration='implicit', seed=3):
    """8×8×8 = 512 spheres on a simple cubic lattice, every neighbour gap at S_min (bridged), no
    gravity, random velocities of 1 mm/s."""
    s_min = 1e-3 * R / 2
    mat = material()
    pitch = 2 * R + s_min
    O.bodies.append([utils.sphere((i * pitch, j * pitch, k * pitch), R, material=mat)
                     for i in range(n_side) for j in range(n_side) for k in range(n_side)])
    rng = random.Random(seed)
    for b in O.bodies:
        b.state.vel = tuple(rng.uniform(-1e-3, 1e-3) for _ in range(3))
    O.engines = viscbridge.engines(gravity=(0, 0, 0), timeStepper=False, guard=False, viscosity=mu,
                                   sMin=s_min, formationDistance=2 * s_min, minRadius=R, integration=integration)
    O.dt = 0.2 * criteria.rayleigh_time(R, RHO, 1e7, 0.3)  # the Hertz collision step


def test_dense_packing_at_the_hertz_step_never_gains_kinetic_energy():
    lattice(integration='implicit')
    ke0 = utils.kineticEnergy()
    total_mass = sum(b.state.mass for b in O.bodies)
    momentum = sum((b.state.mass * b.state.vel for b in O.bodies), Vector3.Zero)
    ke_rigid = 0.5 * momentum.squaredNorm() / total_mass  # the bridges cannot damp the lattice's own drift
    ke = Recorder(lambda: utils.kineticEnergy())
    O.run(100, True)
    bridges = sum(1 for i in O.interactions if i.isReal and i.phys.bridge)
    assert bridges >= 3 * 7 * 64  # every lattice neighbour pair
    t_v = decay_time_pair(1000.0, 1e-3 * R / 2)
    assert O.dt / t_v > 5e4  # the explicit limit is 2 t_v
    assert all(b <= a * (1 + 1e-9) for a, b in zip([ke0] + ke.rows, ke.rows)), 'kinetic energy grew'
    assert ke.rows[-1] - ke_rigid < 1e-3 * (ke0 - ke_rigid)
    assert solver().fallbacks == 0 and solver().residual <= solver().tolerance
    print('implicit lattice: %d bridges, Δt = %.3g s = %.3g t_v, CG iterations/step %.2f, factorisations %d'
          % (bridges, O.dt, O.dt / t_v, solver().totalIterations / solver().solves, solver().factorisations))


def test_dense_packing_explicit_at_the_same_step_blows_up(run_error):
    lattice(integration='explicit')
    O.engines = [yw.ViscBridgeGuard(iterPeriod=1)] + O.engines
    ke0 = utils.kineticEnergy()
    assert re.search('ViscBridgeGuard stopped the run.*A safe dt', run_error(20))
    assert not math.isfinite(utils.kineticEnergy()) or utils.kineticEnergy() > 1e3 * ke0


# --- convergence ---------------------------------------------------------------------------------
def gap_after(integration, dt_over_tv, t_end_over_tv=30.0):
    """Approach of physics.md R1's kind (μ = 1, S0 = 0.01 r, w0 = 5 m/s); the gap at t = 30 t_v.
    The implicit system is solved to 1e-12: the scheme's error is measured, not the solver's."""
    O.reset()
    s_min = 1e-4 * R
    head_on_pair(0.01 * R, 5.0, viscosity=1.0, sMin=s_min, tangentialModel='none', integration=integration)
    for e in O.engines:
        if isinstance(e, yw.ViscBridgeImplicitSolver):
            e.tolerance = 1e-12
    t_v = decay_time_pair(1.0, s_min)
    O.dt = dt_over_tv * t_v
    O.run(int(round(t_end_over_tv / dt_over_tv)), True)
    return gap_and_approach()[0]


def test_implicit_converges_to_explicit_at_first_order():
    """Three steps, halving: the distance to the explicit result (at a step 16× smaller than the
    smallest implicit one) halves too — slope ≈ 1 on log–log."""
    reference = gap_after('explicit', 0.00125)
    steps = [0.08, 0.04, 0.02]
    errors = [abs(gap_after('implicit', f) - reference) for f in steps]
    slopes = [math.log(errors[i] / errors[i + 1]) / math.log(steps[i] / steps[i + 1]) for i in range(2)]
    print('implicit vs explicit: errors %s at Δt/t_v = %s, slopes %s' % (errors, steps, slopes))
    assert all(0.8 <= s <= 1.25 for s in slopes), (errors, slopes)


# --- energy, time step, engines ------------------------------------------------------------------
def test_wet_settling_energy_balance_implicit():
    import test_energy_balance as eb
    eb.wet_box(mu=10.0)
    law = next(f for e in O.engines if isinstance(e, yw.InteractionLoop) for f in e.lawDispatcher.functors)
    assert law.integration == 'explicit'
    O.engines = viscbridge.engines(guard=False, viscosity=10.0, tangentialModel='slip', integration='implicit')
    O.trackEnergy = True
    while O.time < 0.02:
        O.run(1000, True)
    E = dict(O.energy.items())
    assert E['viscDissipNormal'] > 0 and E['viscDissipTangential'] > 0 and E['gravWork'] < 0
    assert abs(O.energy.total()) <= 0.01 * abs(E['gravWork']), E


@pytest.mark.parametrize('mu', [1e-3, 1.0, 100.0, 1000.0])
def test_stepper_governed_by_collisions_with_implicit(mu):
    lattice(mu=mu, integration='implicit')
    O.engines = viscbridge.engines(gravity=(0, 0, 0), guard=False, viscosity=mu, sMin=1e-3 * R / 2,
                                   formationDistance=1e-3 * R, minRadius=R, integration='implicit')
    O.run(5, True)
    ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
    assert sum(1 for i in O.interactions if i.isReal and i.phys.bridge) > 1000
    assert ts.governing in ('rayleigh', 'collision') and math.isinf(ts.dtViscous)
    assert O.dt == pytest.approx(ts.dtCollision, rel=1e-9)


def test_missing_solver_is_a_clear_error_at_the_first_step(run_error):
    lattice(n_side=2)
    O.engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeImplicitSolver)]
    O.engines = [yw.ViscBridgeGuard()] + O.engines
    assert re.search('ViscBridgeImplicitSolver', run_error(1))
    assert O.iter == 0


def test_missing_solver_without_guard_stops_at_the_next_step(run_error):
    """Nothing can be raised inside YADE's interaction loop: the law falls back to explicit forces
    for that step and a guard it schedules raises the error before the next one."""
    lattice(n_side=2)
    O.engines = [e for e in O.engines if not isinstance(e, (yw.ViscBridgeImplicitSolver, yw.ViscBridgeGuard))]
    assert re.search('ViscBridgeImplicitSolver', run_error(5))
    assert O.iter == 1


def test_washino_cannot_be_implicit(run_error):
    with pytest.raises(ValueError, match="washino.*not dissipative"):  # refused when the engines are built
        head_on_pair(1e-5 * R, 0.1, viscosity=1.0, tangentialModel='washino', integration='implicit')
    O.reset()
    head_on_pair(1e-5 * R, 0.1, viscosity=1.0, integration='implicit')
    next(e for e in O.engines if isinstance(e, yw.InteractionLoop)).physDispatcher.functors[0].tangentialModel = 'washino'
    O.dt = 1e-8
    assert re.search("washino.*not dissipative", run_error(3))  # and set afterwards: before the first step
    assert O.iter == 0
    ip2 = next(e for e in O.engines if isinstance(e, yw.InteractionLoop)).physDispatcher.functors[0]
    ip2.tangentialModel = 'goldman'
    O.run(3, True)
    ip2.tangentialModel = 'washino'  # and between two runs
    assert re.search("washino.*not dissipative", run_error(3))
    assert O.iter == 3


def test_solver_parameters_are_validated():
    s = yw.ViscBridgeImplicitSolver()
    for name, value in (('tolerance', 0.0), ('tolerance', 1.5), ('maxIterations', 0), ('preconditioner', 'ilu'),
                        ('factorMemoryLimit', -1.0), ('factorMemoryLimit', float('inf'))):
        with pytest.raises(ValueError, match=name):
            setattr(s, name, value)
    assert (s.tolerance, s.maxIterations, s.preconditioner, s.refreshIterations, s.factorMemoryLimit) == (1e-6, 500, 'auto', 12, 0)  # the defaults, unchanged


def _lattice_run(preconditioner, steps=30, factorMemoryLimit=0):
    """The 10×10×10 lattice at 1000 Pa·s (Δt·C/m ≈ 1e5) after `steps` implicit steps."""
    O.reset()
    lattice(n_side=10)
    solver().preconditioner, solver().tolerance, solver().factorMemoryLimit = preconditioner, 1e-10, factorMemoryLimit
    O.run(steps, True)
    return [b.state.pos for b in O.bodies], [b.state.vel for b in O.bodies], solver()


def test_multigrid_gives_the_factor_s_solution():
    """preconditioner='multigrid' (P15b) solves the same systems as the Cholesky factor: 1000 spheres
    (two levels of aggregates above the factorised coarsest one), velocities within 1e-6 of the
    largest after 30 steps; it reports itself and never needs the direct fallback."""
    pos_c, vel_c, _ = _lattice_run('cholesky')
    pos_m, vel_m, s = _lattice_run('multigrid')
    assert (s.preconditionerInUse, s.fallbacks) == ('multigrid', 0)
    assert s.levels >= 2 and s.residual <= 1e-10
    vmax = max(v.norm() for v in vel_c)
    assert max((a - b).norm() for a, b in zip(vel_c, vel_m)) <= 1e-6 * vmax
    assert max((a - b).norm() for a, b in zip(pos_c, pos_m)) <= 1e-6 * R
    print('multigrid: %d levels, %.1f CG iterations per solve, %d refreshes' % (s.levels, s.totalIterations / s.solves, s.factorisations))


def test_auto_takes_the_factor_where_it_fits_and_the_multigrid_where_it_does_not():
    """preconditioner='auto' (the default) factorises while the analysed factor fits in
    factorMemoryLimit (by default half the memory available: a 1000-sphere lattice's factor, a few
    MB, does), and takes the multigrid, with the same solution, when it does not."""
    pos_c, vel_c, s = _lattice_run('auto')
    assert (s.preconditionerInUse, s.fallbacks) == ('cholesky', 0)
    fits = s.factorBytes
    assert 36 * 8 * s.factorBlocks <= fits <= 1e8  # at least its 6×6 blocks' numbers; a few MB
    pos_m, vel_m, s = _lattice_run('auto', factorMemoryLimit=fits / 2)
    assert (s.preconditionerInUse, s.fallbacks, s.factorBytes) == ('multigrid', 0, fits)
    vmax = max(v.norm() for v in vel_c)
    assert max((a - b).norm() for a, b in zip(vel_c, vel_m)) <= 1e-6 * vmax
    assert max((a - b).norm() for a, b in zip(pos_c, pos_m)) <= 1e-6 * R
