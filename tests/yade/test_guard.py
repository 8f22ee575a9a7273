"""ViscBridgeGuard stops a run before a blow-up spreads, and says why."""
import math
import re

import pytest
from yade import O, utils
import yade.wrapper as yw

import viscbridge
import viscbridge.scan as scan
from wetpairs import R, head_on_pair, material


def guard():
    return next(e for e in O.engines if isinstance(e, yw.ViscBridgeGuard))


@pytest.fixture(scope='module')
def bed(tmp_path_factory):
    return scan.dry_bed(scan.normalize_case(dict(n=120, seed=3)), str(tmp_path_factory.mktemp('beds')))


def wet_bed(path, mu=10.0):
    trial = scan._Trial(scan.normalize_case(dict(n=120, seed=3, viscosity=mu)), path)
    trial.prepare()
    O.engines = [e for e in O.engines if not isinstance(e, (yw.ViscBridgeTimeStepper, yw.ViscBridgeGuard))]
    O.engines = [yw.ViscBridgeGuard(iterPeriod=5)] + O.engines


def test_blow_up_is_stopped_with_a_diagnosis(bed, run_error):
    wet_bed(bed)
    O.run(1, True)
    t_v = min(i.phys.mEff / i.phys.viscousStepCoefficient for i in O.interactions if i.isReal and i.phys.bridge)
    O.dt = 6 * t_v  # three times the explicit pair limit of the stiffest bridge
    start = O.iter
    msg = run_error(500)
    assert O.iter - start < 60, 'stopped within a few checks'
    assert msg == guard().lastError
    # names the body, its interaction with the coefficients, the criterion and a safe Δt
    assert re.search(r'Body #\d+ at \(', msg)
    assert re.search(r'interaction #\d+\+#\d+: gap S = [-0-9.e]+ m with a bridge, C_n = [0-9.e+]+ N·s/m', msg)
    assert 'explicit viscous pair limit dt < 2 m*/(C_n + w_t C_t)' in msg
    safe = float(re.search(r'A safe dt for the current contacts: ([0-9.e+-]+) s', msg).group(1))
    assert 0 < safe < t_v
    assert not O.running


def test_nan_is_stopped_and_names_the_body(bed, run_error):
    wet_bed(bed, mu=1.0)
    O.dt = 1e-9
    O.run(10, True)
    victim = next(b.id for b in O.bodies if b.dynamic)
    O.bodies[victim].state.vel = (float('nan'), 0, 0)
    assert re.search(r'body #%d has a NaN or inf position or velocity' % victim, run_error(20))


def test_nan_on_a_wall_is_stopped_and_names_the_wall(bed, run_error):
    """A body whose motion is prescribed takes no part in the energy sums: gone NaN, it would let
    the spheres fall through it without a word."""
    wet_bed(bed, mu=1.0)
    O.dt = 1e-9
    O.run(10, True)
    wall = next(b.id for b in O.bodies if not b.dynamic)
    O.bodies[wall].state.vel = (float('nan'), 0, 0)
    start = O.iter
    msg = run_error(50)
    assert re.search(r'body #%d, whose motion is prescribed .* has a NaN or inf position or velocity' % wall, msg), msg
    assert O.iter - start <= 2 * guard().iterPeriod


def test_a_stable_run_is_left_alone(bed):
    wet_bed(bed, mu=1.0)
    O.engines = O.engines + []  # the guard of wet_bed, with the stepper back in
    loop_at = next(k for k, e in enumerate(O.engines) if isinstance(e, yw.InteractionLoop))
    engines = list(O.engines)
    engines.insert(loop_at + 1, yw.ViscBridgeTimeStepper())
    O.engines = engines
    O.run(300, True)
    g = guard()
    assert g.checks >= 50 and g.lastError == ''
    assert 0 < g.kineticEnergy <= g.energyIn * g.energyMargin


def test_moving_wall_work_closes_the_energy_balance():
    """A wall pushed into a wet pair: what it does appears as boundaryWork in O.energy."""
    head_on_pair(1e-3 * R, 0.0, viscosity=1.0, tangentialModel='slip')
    O.engines = [yw.ViscBridgeGuard()] + O.engines
    wall = O.bodies.append(utils.wall(3 * R + 0.002 * R, axis=0))  # just right of sphere 1
    O.bodies[wall].state.vel = (-0.01, 0, 0)  # kinematic: pushes the pair to the left
    O.bodies[0].state.blockedDOFs = 'xyzXYZ'  # sphere 0 held
    O.trackEnergy = True
    O.dt = 2e-9
    O.run(50000, True)
    assert O.interactions.has(1, wall) and O.interactions[1, wall].isReal
    E = dict(O.energy.items())
    assert E['boundaryWork'] < 0  # energy put in (YADE's sign, as gravWork)
    assert abs(O.energy.total()) <= 0.01 * abs(E['boundaryWork']), E


def sphere_on_turning_floor(rotationAxis):
    mat = material()
    floor = O.bodies.append(utils.wall(0, axis=2, material=mat))
    O.bodies.append(utils.sphere((2 * R, 0, R * 1.001), R, material=mat))
    turn = yw.RotationEngine(ids=[floor], rotationAxis=rotationAxis, angularVelocity=5.0, label='turnFloor')
    O.engines = viscbridge.engines(viscosity=1.0, kinematic=[turn])
    O.dt = 1e-7


def test_a_wall_turned_about_an_axis_in_its_plane_is_refused_at_the_first_step(run_error):
    """A YADE Wall cannot tilt: turned about x it would only give its contacts the velocity ω × r."""
    sphere_on_turning_floor((1, 0, 0))
    message = run_error(1)
    assert O.iter <= 1 and message.startswith('Body #0 is a Wall'), message
    assert "RotationEngine 'turnFloor'" in message and 'facets' in message and len(message) < 400


def test_a_wall_turned_about_its_normal_is_a_turntable():
    sphere_on_turning_floor((0, 0, 1))
    O.run(200, True)
    assert O.bodies[0].state.angVel[2] == pytest.approx(5.0)


# --- the guard tells the truth --------------------------------------------------------------------
def test_a_kick_between_runs_is_a_new_start_not_a_blow_up(bed):
    """Velocities changed by hand between two O.run() calls: the next run starts from them."""
    wet_bed(bed, mu=1.0)
    O.dt = 1e-9
    O.run(50, True)
    g = guard()
    before = g.rebaselines
    for b in O.bodies:
        if b.dynamic:
            b.state.vel = b.state.vel + (0, 0, 0.2)  # an impact: far more energy than the bed had
    O.run(200, True)
    assert g.lastError == '' and g.rebaselines > before
    assert g.checks >= 20


def test_rebaseline_by_hand_between_single_steps(bed):
    wet_bed(bed, mu=1.0)
    O.dt = 1e-9
    for _ in range(30):
        O.step()
    moved = next(b for b in O.bodies if b.dynamic)
    moved.state.vel = (0.3, 0, 0)
    guard().rebaseline()
    for _ in range(40):
        O.step()
    assert guard().lastError == ''


def test_a_blow_up_is_still_caught_across_many_short_runs(bed, run_error):
    """Each new run takes a new reference but keeps the margin of the last check: an instability
    that grows over many short runs is still stopped."""
    wet_bed(bed)
    O.run(1, True)
    t_v = min(i.phys.mEff / i.phys.viscousStepCoefficient for i in O.interactions if i.isReal and i.phys.bridge)
    O.dt = 2.2 * t_v  # just above the pair limit: slow growth
    message = None
    for _ in range(200):
        try:
            O.run(10, True)
        except RuntimeError as error:
            message = str(error)
            break
        if guard().lastError:
            message = guard().lastError
            break
    assert message and 'ViscBridgeGuard stopped the run' in message


def test_washino_energy_gain_is_blamed_on_the_model(run_error):
    """'washino' is not dissipative: a sphere sliding on a wall without spin gains kinetic energy
    (physics.md P7).  The guard says so and does not offer the current dt as a remedy."""
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, R), R, material=mat)])
    O.bodies[1].state.vel = (0.01, 0, 0)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=1.0, tangentialModel='washino', normalModel='none')
    O.dt = 1e-8
    msg = run_error(200000)
    assert "tangentialModel='washino', which is not dissipative" in msg
    safe = re.search(r'A safe dt for the current contacts: ([0-9.e+-]+) s', msg)
    assert safe is None or float(safe.group(1)) < O.dt
    assert 'a smaller dt is not the remedy' in msg


def test_clumps_are_accepted_with_explicit_integration():
    mat = material()
    O.bodies.append(utils.wall(0, axis=2, material=mat))
    O.bodies.appendClumped([utils.sphere((0, 0, 1.001 * R), R, material=mat), utils.sphere((0, 1.5 * R, 1.001 * R), R, material=mat)])
    O.engines = viscbridge.engines(viscosity=1.0)
    O.dt = 1e-8
    O.run(3000, True)
    assert guard().lastError == '' and guard().checks > 100
    assert all(math.isfinite(c) for b in O.bodies for c in b.state.pos)


@pytest.mark.parametrize('dt', [1e-3, 1e-5])
def test_advice_counts_the_bridge_that_ruptured_before_the_diagnosis(dt, run_error):
    """A sphere resting in a bridge on a wall at a far too large dt: the blow-up tears the bridge
    apart within the 10 steps between two checks, so at the diagnosis no contact is left to bound
    dt.  The advised dt still counts the ruptured bridge — it is below that bridge's explicit limit
    2m*/C(S_min) (P12) — and a run at the advised dt goes on without a stop."""
    def scene(step):
        O.reset()
        mat = material()
        O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, 0.9999 * R), R, material=mat)])
        O.engines = viscbridge.engines(viscosity=1.0, timeStepper=False)
        O.dt = step
    scene(dt)
    O.run(1, True)
    bridge = O.interactions[0, 1].phys
    pair_limit = 2 * bridge.mEff / bridge.viscousStepCoefficient
    msg = run_error(2000)
    assert not any(i.isReal for i in O.interactions)  # the bridge is gone at the diagnosis
    safe = float(re.search(r'A safe dt for the current contacts: ([0-9.e+-]+) s \(half the rigorous bound P14, counting the bridges '
                           r'ruptured since the last check;', msg).group(1))
    assert safe <= 0.5 * pair_limit * 1.001
    scene(safe)
    O.run(20000, True)
    assert guard().lastError == '' and O.interactions[0, 1].phys.bridge


@pytest.mark.parametrize('integration', ['explicit', 'implicit'])
def test_two_dry_spheres_stacked_on_a_floor_are_not_stopped(integration):
    """The simplest scene a user builds: two spheres stacked touching on a floor, no film, so no
    bridge and nothing damps them.  They bounce and climb back towards where they were released;
    the guard stopped them at step 160 ('kinetic + elastic energy exceeds…'), comparing the
    leapfrog's energy error of the bounce with the little energy left once gravity took it back.
    The energy they held is the scale (physics.md E5)."""
    r = 0.5e-3
    O.bodies.append([utils.wall(0, axis=2), utils.sphere((0, 0, r), r), utils.sphere((0, 0, 3 * r), r)])
    O.engines = viscbridge.engines(viscosity=5.0, liquidModel='film', integration=integration)
    O.dt = 1e-6
    O.run(2000, True)
    assert guard().checks >= 100
    top = O.bodies[2].state.pos[2]
    assert 2.9 * r < top < 3.01 * r, 'still bouncing on the lower sphere, not flown off: z = %g' % top


def test_a_blow_up_after_a_bounce_is_still_stopped(run_error):
    """The margin's scale is the most energy the scene held, not what it holds now: an explicit
    viscous blow-up that starts once the stack has bounced back up is still stopped.  The spheres
    get their films (a bridge forms) after 300 steps, at a Δt 10× the explicit viscous limit."""
    r = 0.5e-3
    O.bodies.append([utils.wall(0, axis=2), utils.sphere((0, 0, r), r), utils.sphere((0, 0, 3 * r), r)])
    O.engines = viscbridge.engines(viscosity=5.0, liquidModel='film', integration='explicit', timeStepper=False) + [
        yw.PyRunner(iterPeriod=300, command='import viscbridge.liquid as l; l.add([1, 2], 1e-12) if O.iter == 300 else None')]
    O.dt = 4e-6  # dry: a quarter of the collision limit
    msg = run_error(2000)
    assert O.iter > 300, 'no false stop before the bridges formed'
    assert 'exceeds' in msg or 'NaN' in msg
    assert next(e for e in O.engines if isinstance(e, yw.ViscBridgeLiquid)).formed >= 1
