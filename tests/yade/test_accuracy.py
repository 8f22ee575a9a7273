"""Accuracy as the input (physics.md §7a): a tolerance instead of a time step.  The run meets a
closed form at each tolerance, the controller grows Δt on a bed at rest and shrinks it at an impact,
integration='auto' switches schemes mid-run without breaking the energy balance, and bad tolerances
are refused with the parameter named."""
import math

import pytest
from scipy.integrate import quad, solve_ivp
from yade import O, utils
import yade.wrapper as yw

import viscbridge
from viscbridge.scenes import settling
from wetpairs import R, material, wet_box

pytestmark = pytest.mark.slow  # runs of a few thousand steps


def stepper():
    return next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))


def the_law():
    return next(f for e in O.engines if isinstance(e, yw.InteractionLoop) for f in e.lawDispatcher.functors)


def approach(accuracy, mu=4e-3, w0=0.1):
    """R1: a head-on Adams–Perchard approach from S0 = 0.1 r to S_min = 1e-4 r (the pair loses 45 %
    of its speed); returns the gap error when the closed form reaches S_min, relative to the distance
    travelled, and the steps taken."""
    S0, s_min = 0.1 * R, 1e-4 * R
    mat = material()
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((2 * R + S0, 0, 0), R, material=mat)])
    O.bodies[0].state.vel, O.bodies[1].state.vel = (0.5 * w0, 0, 0), (-0.5 * w0, 0, 0)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), guard=False, minRadius=R, accuracy=accuracy, viscosity=mu, sMin=s_min,
                                   normalModel='adamsPerchard', tangentialModel='none', formationDistance=1.5 * S0)
    O.dt = 0
    A = 1.8 * mu  # physics.md R1: w(S) = w0 − A ln(S0/S)
    arrival = quad(lambda S: 1 / (w0 - A * math.log(S0 / S)), s_min, S0)[0]
    gap = lambda: (O.bodies[1].state.pos - O.bodies[0].state.pos).norm() - 2 * R  # noqa: E731
    before = (0.0, S0)
    while O.time < arrival:
        before = (O.time, gap())
        O.step()
    at = before[1] + (arrival - before[0]) / (O.time - before[0]) * (gap() - before[1])
    return abs(at - s_min) / (S0 - s_min), O.iter


def test_a_pair_approach_meets_each_tolerance():
    results = {}
    for tol in (1e-1, 1e-2, 1e-3):
        O.reset()
        results[tol] = approach(tol)
        assert results[tol][0] <= tol, (tol, results[tol])
        assert stepper().errorEstimate > 0
    # the tolerance is what sets the steps: a tighter one takes more
    assert results[1e-1][1] < results[1e-2][1] < results[1e-3][1], results


def test_the_controller_grows_dt_at_rest_and_shrinks_it_at_an_impact():
    scene = settling(n=30, viscosity=10.0, accuracy=1e-2, guard=False, trackEnergy=False)
    scene.run(duration=0.06)
    ts = stepper()
    # at rest: the step is the stability limit of the scheme (the collision limit, implicit)
    assert ts.scheme == 'implicit'
    assert ts.governing != 'accuracy' and O.dt == pytest.approx(ts.dtBound, rel=1e-9), (ts.governing, O.dt, ts.dtBound)
    rest = O.dt
    top = max((b for b in O.bodies if isinstance(b.shape, yw.Sphere)), key=lambda b: b.state.pos[2])
    top.state.vel = (0, 0, -0.3)  # an impact on the bed
    shortest = rest
    for _ in range(60):
        O.step()
        shortest = min(shortest, O.dt)
    assert shortest < 0.5 * rest, (shortest, rest)


def settling_estimate(interval, steps=1500, **kw):
    """A 60-sphere bed landing through bridges (implicit), the estimate filtered in full every
    `interval` steps: (the run's error estimate, full filters, solves)."""
    O.reset()
    settling(n=60, viscosity=10.0, integration='implicit', guard=False, trackEnergy=False, **kw)
    stepper().errorFilterInterval = interval
    O.run(steps, True)
    solver = next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver))
    return stepper().errorEstimate, solver.estimateFilters, solver.solves


def test_between_filters_the_estimate_stays_near_the_every_step_one():
    """A1d: filtered in full every 8th step (Δt is the collision limit here, constant), the estimate
    costs an eighth of the filters and stays within 0.8–2× the one filtered every step (what waits
    between filters is relaxed by the factor alone; A1a's second filter at the last full
    filter's share is an approximation either way)."""
    every, filters1, solves1 = settling_estimate(1)
    eighth, filters8, solves8 = settling_estimate(8)
    assert solves1 > 500 and filters1 == solves1, (filters1, solves1)
    assert solves8 / 8 - 1 <= filters8 <= solves8 / 8 + 10, (filters8, solves8)
    assert 0.8 * every <= eighth <= 2 * every, (every, eighth)
    O.saveTmp('filtered')
    O.loadTmp('filtered')
    assert stepper().errorFilterInterval == 8  # a saved run keeps its interval


def test_the_estimate_is_filtered_every_step_where_the_tolerance_sets_dt():
    """A1d: the controller needs the full estimate of every step it sizes (the stiffening pair,
    implicit, accuracy 1e-3, errorFilterInterval 8)."""
    O.reset()
    T, _ = stiffening_pair_scene()
    ts = stepper()
    ts.accuracy, ts.errorFilterInterval = 1e-3, 8
    solver = next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver))
    governed, unfiltered = 0, []
    while O.time < T:
        before = (solver.estimateFilters, solver.solves)
        O.step()
        if solver.solves > before[1] and solver.estimateFilters == before[0] and ts.governing == 'accuracy':
            unfiltered.append(O.iter)
        governed += ts.governing == 'accuracy' and solver.solves > before[1]
    assert governed > 50 and not unfiltered, (governed, unfiltered[:10])


def test_switching_schemes_mid_run_keeps_the_energy_balance():
    """A dry cloud runs explicit; as it lands, bridges form and the stepper switches to implicit."""
    wet_box(n=40, mu=10.0, accuracy=1e-2)
    ts = stepper()
    switch = None
    while O.time < 0.03:
        O.run(100, True)
        if switch is None and ts.schemeSwitches:
            switch = (O.iter, sum(1 for i in O.interactions if i.phys.bridge))
    # not at the start: once the landing spheres had formed bridges
    assert switch is not None and switch[0] > 100 and switch[1] > 0, switch
    assert ts.scheme == 'implicit'
    E = dict(O.energy.items())
    assert sum(1 for i in O.interactions if i.phys.bridge) > 20
    assert abs(O.energy.total()) <= 0.01 * abs(E['gravWork']), E


def test_the_chosen_scheme_is_the_scenes_and_a_saved_run_resumes_it():
    """autoIntegration chooses the scheme without touching the law: the law keeps the scheme the run
    started with (integration) and runs the stepper's choice (integrationInUse); a run saved after
    the switch to implicit goes on implicitly from its first loaded step, as the run never saved."""
    wet_box(n=40, mu=10.0, accuracy=1e-2)
    ts, law = stepper(), the_law()
    assert law.integrationInUse == law.integration == 'explicit'
    while not ts.schemeSwitches and O.time < 0.03:
        O.run(20, True)
    assert ts.scheme == law.integrationInUse == 'implicit' and law.integration == 'explicit', (ts.scheme, law.integrationInUse)
    O.saveTmp('switched')
    O.run(60, True)
    uninterrupted = [tuple(b.state.pos) for b in O.bodies]
    O.loadTmp('switched')
    law = the_law()
    assert law.integrationInUse == 'implicit' and law.integration == 'explicit'
    O.run(60, True)
    assert [tuple(b.state.pos) for b in O.bodies] == pytest.approx(uninterrupted, rel=1e-12, abs=1e-15)


def capillary_pair_estimate(dt0):
    """A pair at rest 0.02 r apart pulled together by its bridge's capillary force against the viscous
    one (implicit, the stepper from O.dt = dt0, 0: its limit at once) for 10 ms; the run's estimate."""
    mat = material()
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((2.02 * R, 0, 0), R, material=mat)])
    O.engines = viscbridge.engines(gravity=(0, 0, 0), guard=False, minRadius=R, viscosity=1.0, sMin=1e-4 * R, integration='implicit',
                                   normalModel='adamsPerchard', tangentialModel='slip', formationDistance=0.03 * R,
                                   capillaryModel='willett', surfaceTension=0.07, bridgeVolumeRel=0.01)
    O.dt = dt0
    O.stopAtTime = 1e-2
    O.run()
    O.wait()
    assert (O.bodies[1].state.pos - O.bodies[0].state.pos).norm() - 2 * R < 0.01 * R  # it has closed most of the gap
    return stepper().errorEstimate


def test_a_pull_the_bridges_balance_makes_no_leapfrog_offset():
    """A1b under the implicit scheme: the capillary pull of a closing pair is balanced by the viscous
    force at every step, so a Δt that grows (from 1e-8 s by the stepper's 10 % per step) moves the
    pair no differently from a constant one.  The offsets the pull starts are relaxed by this step's
    matrix, not by the factor of a gap 100 times wider: relaxed by that one, they stayed as large as
    the pair's speed and the estimate read 0.56 where the constant-step run reads 1e-3."""
    constant = capillary_pair_estimate(0)
    O.reset()
    growing = capillary_pair_estimate(1e-8)
    assert 0 < constant < 1e-2 and growing < 2 * constant, (growing, constant)


def falling(bridged=False):
    """A sphere (and, bridged, a second one bridged to it) falling at Δt = 1e-6 s for 20 steps, then
    with Δt growing 10 % per step up to 4e-6 s; returns the stepper."""
    mat = material()
    O.bodies.append(utils.sphere((0, 0, 0), R, material=mat))
    if bridged:
        O.bodies.append(utils.sphere((2.02 * R, 0, 0), R, material=mat))
    O.engines = viscbridge.engines(integration='implicit', guard=False, minRadius=R, viscosity=10.0, formationDistance=0.05 * R)
    ts = stepper()
    ts.maxDt = 1e-6
    O.dt = 0
    O.run(20, True)
    assert sum(1 for i in O.interactions if i.isReal and i.phys.bridge) == (1 if bridged else 0)
    ts.maxDt = 4e-6  # the stepper grows dt by 10 % per step up to it
    return ts


@pytest.mark.parametrize('bridged', [False, True])
def test_the_estimate_of_a_free_fall_is_its_true_error(bridged):
    """A1b: YADE's leapfrog moves a falling sphere ½g Σ Δt_n² further than ½gt² (its velocity stands
    for the middle of each step); the stepper's estimate is that offset, signed, and nothing else —
    a change of Δt is not a change of the force (A1: the estimate per unit time).  Δt grows 10 % per
    step from 1e-6 to 4e-6 s; a free sphere (the stepper's own estimate) and a bridged pair falling
    as one (the implicit solver's, whose bridges do not damp a common motion)."""
    ts = falling(bridged)
    O.run(40, True)
    assert O.dt == pytest.approx(4e-6, rel=1e-12)
    fall = 0.5 * 9.81 * O.time ** 2
    true_error = abs(O.bodies[0].state.pos[2] + fall) / fall
    assert true_error > 0.01  # the leapfrog's first-order error at this Δt
    assert ts.errorEstimate == pytest.approx(true_error, rel=0.01)


def test_a_saved_run_resumes_its_estimate_exactly():
    """The last step's forces (A1) and offsets (A1b) are part of the run's state: a scene saved and
    loaded goes on estimating the same error as the run that was never saved, to rounding.  The
    sphere fell while Δt grew, then coasts without gravity: a loaded run that restarted its offset
    would give it ½Δt·a = 0 where the run carries the one it fell with, and one without the forces
    would skip its first step's error."""
    falling()
    O.run(40, True)
    next(e for e in O.engines if isinstance(e, yw.NewtonIntegrator)).gravity = (0, 0, 0)
    O.run(10, True)
    O.saveTmp('coasting')
    O.run(30, True)
    uninterrupted = stepper().errorEstimate
    O.loadTmp('coasting')
    O.run(30, True)
    assert stepper().errorEstimate == pytest.approx(uninterrupted, rel=1e-12)


def stiffening_pair_scene(mu=1.0, growth=100.0, integration='implicit', safety=0.5):
    """R1 with a bridge that stiffens `growth`-fold as the pair stops (S0 = 0.1 r to S0/growth).
    Returns T = the approach and 30 relaxation times, and the gap error now against the closed
    form, relative to the distance travelled (a function)."""
    A, S0 = 1.8 * mu, 0.1 * R
    w0 = A * math.log(growth)
    mat = material()
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((2 * R + S0, 0, 0), R, material=mat)])
    O.bodies[0].state.vel, O.bodies[1].state.vel = (0.5 * w0, 0, 0), (-0.5 * w0, 0, 0)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), guard=False, minRadius=R, viscosity=mu, sMin=1e-4 * R, integration=integration,
                                   safety=safety, normalModel='adamsPerchard', tangentialModel='none', formationDistance=1.5 * S0)
    O.dt = 0

    def gap_error():
        exact = solve_ivp(lambda t, S: [-(w0 - A * math.log(S0 / S[0]))], (0, O.time), [S0], method='Radau', rtol=1e-12, atol=1e-20).y[0, -1]
        gap = (O.bodies[1].state.pos - O.bodies[0].state.pos).norm() - 2 * R
        return abs(gap - exact) / (S0 - exact)
    return S0 / w0 + 30 * (S0 / growth) / A, gap_error


def stiffening_pair(steps):
    """The stiffening pair at fixed implicit steps of T/steps, saved half-way; the error at T and the stepper."""
    T, gap_error = stiffening_pair_scene()
    ts = stepper()
    ts.maxDt = T / steps
    O.run(steps // 2, True)
    O.saveTmp('halfway')
    O.run(steps - steps // 2, True)
    return gap_error(), ts


def test_the_explicit_scheme_carries_the_error_its_lagging_bridges_make():
    """A1c under the explicit scheme: the viscous force lags the velocity it damps, and the velocity
    error a step makes stays as long as the bridges' live coefficient takes to relax it — here up to
    1000× longer than P14's rate at S_min says.  At the stepper's limit and below it the estimate
    neither falls below the true error (it was 60–150× below when relaxed at P14's rate) nor more
    than 4× above it, and halves with Δt as the error does."""
    found = {}
    for safety in (0.5, 0.125):
        O.reset()
        T, gap_error = stiffening_pair_scene(integration='explicit', safety=safety)
        O.stopAtTime = T
        O.run()
        O.wait()
        found[safety] = (gap_error(), stepper().errorEstimate)
        assert found[safety][0] <= found[safety][1] <= 4 * found[safety][0], found
    assert 3 < found[0.5][0] / found[0.125][0] < 5 and 3 < found[0.5][1] / found[0.125][1] < 5, found  # first order


def test_a_stiffening_bridge_is_estimated_not_filtered_away():
    """A1c: a bridge whose coefficient grows along a step (C ∝ 1/S, 100-fold here) gives the pair an
    impulse error that backward Euler does not relax away: the pair stops at a shifted gap, a
    first-order error.  The estimate follows it (not below it: it was 8–620× below before A1c),
    halves with Δt as the error does, and a run loaded half-way carries it on exactly."""
    coarse, ts = stiffening_pair(160)
    estimate_coarse = ts.errorEstimate
    O.loadTmp('halfway')
    O.run(80, True)
    assert stepper().errorEstimate == pytest.approx(estimate_coarse, rel=1e-12)
    O.reset()
    fine, ts = stiffening_pair(640)
    assert 2.5 < coarse / fine < 6, (coarse, fine)  # first order
    for error, estimate in ((coarse, estimate_coarse), (fine, ts.errorEstimate)):
        assert error <= estimate <= 10 * error, (error, estimate)
    assert 2.5 < estimate_coarse / ts.errorEstimate < 6


def test_a_bridge_forming_is_a_jump_of_the_model_whose_steps_count_their_own_error():
    """A1, A1e: a bridge that forms between spheres closing at 0.1 m/s takes half their relative
    speed in its first implicit step at 30 Pa·s (z = Δt·C/m* ≈ 1).  The next step's trapezoidal
    companion must not compare against that jump of the model (it would report the jump, not an
    error); the formation step and the next count their own error instead, the backward-Euler step
    against its trapezoidal companion on the viscous force — which, as the decay's, falls with the
    relative speed it acts on, step after step."""
    mat = material()
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((2.2 * R, 0, 0), R, material=mat)])
    O.bodies[0].state.vel, O.bodies[1].state.vel = (0.05, 0, 0), (-0.05, 0, 0)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), integration='implicit', guard=False, minRadius=R, viscosity=30.0,
                                   formationDistance=0.1 * R, tangentialModel='none')
    ts = stepper()
    ts.maxDt = 1e-6
    O.dt = 0
    closing = lambda: O.bodies[0].state.vel[0] - O.bodies[1].state.vel[0]  # noqa: E731
    while not any(i.phys.bridge for i in O.interactions if i.isReal):
        before = closing()
        O.step()
        assert O.time < 1e-3, 'no bridge formed'
    assert closing() < 0.6 * before  # the formation step: a jump of the relative speed
    errors, speeds = [], [before, closing()]
    for _ in range(3):
        O.step()
        errors.append(ts.stepError)  # of the step before: the formation step's, the next one's, …
        speeds.append(closing())
    # each step's error in proportion to the speed it acted on (the jump itself would be 2-3x its share)
    for k in range(2):
        assert errors[k + 1] / errors[k] == pytest.approx(speeds[k + 1] / speeds[k], rel=0.2), (errors, speeds)


@pytest.mark.parametrize('bad', [0, -1e-2, 1, 2.0, float('nan'), float('inf'), 'tight'])
def test_bad_tolerances_are_refused_with_the_parameter_named(bad):
    with pytest.raises(ValueError, match='accuracy'):
        viscbridge.engines(viscosity=1.0, accuracy=bad)
    with pytest.raises(ValueError, match='accuracy'):
        settling(n=5, accuracy=bad)


@pytest.mark.parametrize('bad', [-0.5, 1.0, 3.0, float('nan')])
def test_the_stepper_refuses_a_bad_tolerance_and_keeps_its_own(bad):
    ts = yw.ViscBridgeTimeStepper(accuracy=1e-2)
    with pytest.raises(ValueError, match='accuracy'):
        ts.accuracy = bad
    assert ts.accuracy == 1e-2


def test_a_tolerance_needs_the_time_stepper():
    with pytest.raises(ValueError, match='accuracy'):
        viscbridge.engines(viscosity=1.0, accuracy=1e-2, timeStepper=False)
    with pytest.raises(ValueError, match="integration='auto'"):
        viscbridge.engines(viscosity=1.0, integration='auto', timeStepper=False)


def wall_stop(steps, T=6e-5, mu=100.0):
    """A sphere (r = 5 mm) thrown at 3 m/s at a wall through a bridge that forms at once and stops it
    within about 10⁻⁵ s (Adams–Perchard); implicit steps of T/steps.  The kinetic energy after every
    step, as (t, K), and the stepper."""
    r = 5e-3
    mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, r + 0.09 * r), r, material=mat)])
    O.bodies[1].state.vel = (0, 0, -3.0)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=mu, integration='implicit', guard=False, minRadius=r, sMin=1e-4 * r,
                                   normalModel='adamsPerchard', tangentialModel='slip', formationDistance=0.1 * r)
    stepper().maxDt = T / steps
    O.dt = 0
    trace = [(0.0, utils.kineticEnergy())]
    while O.time < T * (1 - 1e-9):
        O.step()
        trace.append((O.time, utils.kineticEnergy()))
    return trace, stepper()


def test_a_decay_carries_the_error_of_its_velocity_history():
    """A1e: backward Euler follows a viscous decay a little slower than it is at every step, and the
    errors add up while the speed decays (n z²/2 of it after n steps of z = Δt·C/m*), the first
    steps' (the bridge formed at once) included.  The estimate of the kinetic-energy history's error,
    ∫|K − K_ref| dt / ∫K_ref dt, is within 2× of the true one (measured 1.1–1.3×) and falls with Δt
    as the error does."""
    import numpy as np
    reference, _ = wall_stop(2048)
    tr, kr = np.array(reference).T
    found = {}
    for steps in (32, 128):
        O.reset()
        trace, ts = wall_stop(steps)
        t, k = np.array(trace).T
        run = np.exp(np.interp(tr, t, np.log(k)))
        found[steps] = (np.trapezoid(np.abs(run - kr), tr) / np.trapezoid(kr, tr), ts.errorEstimate)
    for error, estimate in found.values():
        assert error / 2 <= estimate <= 2 * error, found
    assert 2.5 < found[32][1] / found[128][1] < 6, found


def wall_impact(mu, accuracy):
    """A sphere of 5 mm thrown at 3 m/s onto a wall through a bridge that forms 0.5 mm above it
    (bench/accuracy_case.py's wall), with the tolerance `accuracy`."""
    r, S0 = 5e-3, 0.5e-3
    mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, r + 0.9 * S0), r, material=mat)])
    O.bodies[1].state.vel = (0, 0, -3.0)
    O.engines = viscbridge.engines(viscosity=mu, guard=False, minRadius=r, accuracy=accuracy, sMin=1e-4 * r, normalModel='adamsPerchard',
                                   tangentialModel='slip', formationDistance=S0)
    O.dt = 0


def test_the_controller_tightens_for_the_accumulated_error_and_a_saved_run_keeps_it():
    """A4c: the wall impact at 100 Pa·s with accuracy=1e-4 accumulates, in the bridge's decay, more
    velocity error than half the tolerance allows: the controller holds the steps' own errors to a
    share of it below 1, which a saved and loaded run keeps, step for step."""
    wall_impact(100.0, 1e-4)
    ts = stepper()
    while ts.errorTightening == 1:
        O.step()
        assert O.iter < 20000, 'the controller never tightened'
    O.run(50, True)
    assert ts.errorTightening < 1
    O.saveTmp('tightened')
    steps = []
    for _ in range(30):
        O.step()
        steps.append((O.dt, stepper().errorTightening))
    O.loadTmp('tightened')
    for dt, tightening in steps:
        O.step()
        assert (O.dt, stepper().errorTightening) == pytest.approx((dt, tightening), rel=1e-12)
