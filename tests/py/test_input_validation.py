"""Every user-settable parameter of every ViscBridge class and function: bad input is a Python
exception naming the parameter, its value and the allowed range — on assignment, or at the latest
at the first step.  (Ip2_FrictMat_FrictMat_ViscBridgePhys: test_attribute_validation.py.)"""
import math
import re

import pytest
from yade import O, utils
import yade.wrapper as yw

import viscbridge
import viscbridge.scan as scan
import viscbridge.scenes as scenes
from wetpairs import R, material

ATTRIBUTES = [
    (yw.Law2_ScGeom_ViscBridgePhys_HertzViscous, 'integration', 'semi', "'explicit', 'implicit'"),
    (yw.ViscBridgeTimeStepper, 'safety', 0.0, '(0, 1]'),
    (yw.ViscBridgeTimeStepper, 'safety', 1.5, '(0, 1]'),
    (yw.ViscBridgeTimeStepper, 'maxGrowth', 0.5, '[1,'),
    (yw.ViscBridgeTimeStepper, 'rayleighFraction', 0.0, '(0, 1]'),
    (yw.ViscBridgeTimeStepper, 'maxDt', -1e-6, '>= 0'),
    (yw.ViscBridgeImplicitSolver, 'tolerance', 0.0, '(0, 1)'),
    (yw.ViscBridgeImplicitSolver, 'tolerance', 1.0, '(0, 1)'),
    (yw.ViscBridgeImplicitSolver, 'maxIterations', 0, '[1,'),
    (yw.ViscBridgeImplicitSolver, 'refreshIterations', 0, '[1,'),
    (yw.ViscBridgeImplicitSolver, 'preconditioner', 'ilu', "'cholesky', 'jacobi'"),
    (yw.ViscBridgeGuard, 'iterPeriod', 0, '[1,'),
    (yw.ViscBridgeGuard, 'energyMargin', 0.9, '[1,'),
    (yw.ViscBridgeGuard, 'energyFloor', -1.0, '>= 0'),
    (yw.Ig2_Wall_Sphere_ViscBridgeScGeom, 'detectionDistance', -1e-6, '>= 0'),
    (yw.Ig2_Facet_Sphere_ViscBridgeScGeom, 'detectionDistance', -1e-6, '>= 0'),
]


@pytest.mark.parametrize('cls,name,value,allowed', ATTRIBUTES, ids=lambda x: getattr(x, '__name__', str(x)))
def test_attribute_rejected_on_assignment(cls, name, value, allowed):
    obj = cls()
    before = getattr(obj, name)
    with pytest.raises(ValueError) as err:
        setattr(obj, name, value)
    msg = str(err.value)
    assert name in msg and allowed in msg and (str(value) in msg or '%g' % value in msg), msg
    assert getattr(obj, name) == before  # the previous value stays


@pytest.mark.parametrize('cls,name,value,allowed', ATTRIBUTES, ids=lambda x: getattr(x, '__name__', str(x)))
def test_attribute_rejected_in_constructor(cls, name, value, allowed):
    with pytest.raises(ValueError, match=name):
        cls(**{name: value})


# --- what can only be checked at the first step (ViscBridgeGuard, first engine) -------------------
def small_scene(**kw):
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, 1.001 * R), R, material=mat)])
    O.engines = viscbridge.engines(viscosity=1.0, **kw)
    O.dt = 1e-7


def test_non_positive_dt_at_first_step(run_error):
    small_scene()
    O.dt = 0.0  # YADE itself accepts it (a negative value would switch its time stepper on)
    assert re.search(r'O\.dt=0 is out of range; allowed: > 0', run_error(1))
    assert O.iter == 0


def test_body_without_frictmat_at_first_step(run_error):
    small_scene()
    O.bodies.append(utils.sphere((0, 0, 5 * R), R, material=yw.ElastMat(young=1e7, density=2500)))
    assert re.search('Body #2 has material ElastMat; allowed.*FrictMat', run_error(1))
    assert O.iter == 0


def test_law_without_its_ip2_at_first_step(run_error):
    small_scene()
    loop = next(e for e in O.engines if isinstance(e, yw.InteractionLoop))
    idx = [type(e) for e in O.engines].index(yw.InteractionLoop)
    engines = list(O.engines)
    engines[idx] = yw.InteractionLoop(list(loop.geomDispatcher.functors), [yw.Ip2_FrictMat_FrictMat_MindlinPhys()],
                                      list(loop.lawDispatcher.functors))
    O.engines = engines
    assert re.search('needs Ip2_FrictMat_FrictMat_ViscBridgePhys', run_error(1))


def test_ip2_without_its_law_at_first_step(run_error):
    small_scene()
    loop = next(e for e in O.engines if isinstance(e, yw.InteractionLoop))
    idx = [type(e) for e in O.engines].index(yw.InteractionLoop)
    engines = list(O.engines)
    engines[idx] = yw.InteractionLoop(list(loop.geomDispatcher.functors), list(loop.physDispatcher.functors),
                                      [yw.Law2_ScGeom_FrictPhys_CundallStrack()])
    O.engines = engines
    assert re.search('needs Law2_ScGeom_ViscBridgePhys_HertzViscous', run_error(1))


def test_damped_newton_with_implicit_at_first_step(run_error):
    small_scene(integration='implicit')
    next(e for e in O.engines if isinstance(e, yw.NewtonIntegrator)).damping = 0.2
    assert re.search('NewtonIntegrator.damping=0.2.*allowed: 0', run_error(1))


def test_step_raises_value_error_directly():
    """O.step() runs in the caller's thread: the exception keeps its type."""
    small_scene()
    O.dt = 0.0
    with pytest.raises(ValueError, match='dt'):
        O.step()


# --- Python functions ----------------------------------------------------------------------------
@pytest.mark.parametrize('kw,name', [
    (dict(gravity=(0, 0)), 'gravity'), (dict(gravity=(0, 0, float('nan'))), 'gravity'),
    (dict(integration='semi'), 'integration'), (dict(safety=0), 'safety'), (dict(safety=2), 'safety'),
    (dict(viscosity=-1), 'viscosity'), (dict(sMinRel=0), 'sMinRel'), (dict(colour=1), 'colour'),
    (dict(formationDistance=1e-5, minRadius=-1), 'minRadius'),
])
def test_engines_arguments(kw, name):
    with pytest.raises(ValueError, match=name):
        viscbridge.engines(**kw)


@pytest.mark.parametrize('kw,name', [
    (dict(n=0), 'n'), (dict(radius=-1e-3), 'radius'), (dict(density=0), 'density'), (dict(young=0), 'young'),
    (dict(sizeRatio=6), 'sizeRatio'), (dict(poisson=0.5), 'poisson'), (dict(friction=-0.1), 'friction'),
    (dict(dt=0), 'dt'), (dict(safety=0), 'safety'), (dict(initialSpeed=-1), 'initialSpeed'),
    (dict(gravity=0), 'gravity'), (dict(viscosity=-1), 'viscosity'), (dict(bridgeVolume=-1), 'bridgeVolume'),
    (dict(n=500, width=4e-3, height=2e-3), 'width or height'), (dict(normalModel='x'), 'normalModel'),
])
def test_settling_arguments(kw, name):
    with pytest.raises(ValueError, match=name):
        scenes.settling(**dict(dict(n=20), **kw))


@pytest.mark.parametrize('kw,name', [
    (dict(), 'exactly one'), (dict(duration=1e-3, steps=10), 'exactly one'), (dict(duration=-1.0), 'duration'),
    (dict(steps=0), 'steps'), (dict(steps=1.5), 'steps'), (dict(steps=10, points=0), 'points'),
])
def test_settling_run_arguments(kw, name):
    s = scenes.settling(n=20, viscosity=0.1)
    with pytest.raises(ValueError, match=name):
        s.run(**kw)


@pytest.mark.parametrize('kw,name', [
    (dict(n=0), 'n'), (dict(n=2.5), 'n'), (dict(steps=0), 'steps'), (dict(tolerance=0), 'tolerance'),
    (dict(perturbation=-1), 'perturbation'), (dict(viscosity=-1), 'viscosity'), (dict(radius=0), 'radius'),
    (dict(sizeRatio=0.5), 'sizeRatio'), (dict(integration='rk4'), 'integration'), (dict(colour=1), 'colour'),
])
def test_scan_case_fields(kw, name):
    with pytest.raises(ValueError, match=name):
        scan.normalize_case(kw)


def test_scan_jobs(tmp_path):
    with pytest.raises(ValueError, match='jobs'):
        scan.run_cases([], str(tmp_path), jobs=0)


# --- bodies the law cannot handle: refused before they can give dt = 0, NaN or time running back ---
@pytest.mark.parametrize('radius', [0.0, -R, float('nan')])
@pytest.mark.parametrize('with_guard', [True, False])
def test_bad_sphere_radius_is_refused_before_a_step(radius, with_guard, run_error):
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, 1.001 * R), R, material=mat)])
    O.bodies[1].shape.radius = radius
    O.engines = viscbridge.engines(viscosity=1.0, guard=with_guard)
    O.dt = 1e-7
    msg = run_error(5)
    assert re.search(r'Body #1: Sphere\.radius=(0|-0\.0005|nan) is out of range; allowed: > 0', msg), msg
    assert O.time <= 1e-7 and all(math.isfinite(c) for b in O.bodies for c in b.state.pos)


def test_zero_mass_is_refused(run_error):
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, 1.001 * R), R, material=mat)])
    O.bodies[1].state.mass = 0
    O.engines = viscbridge.engines(viscosity=1.0)
    O.dt = 1e-7
    assert 'State.mass=0 is out of range' in run_error(5)


@pytest.mark.parametrize('interval', [0, 5000])
def test_a_time_step_update_interval_other_than_1_is_an_error(run_error, interval):
    """0 would divide by zero in YADE's TimeStepper; 5000 (a habit from GlobalStiffnessTimeStepper)
    skipped the stepper's correction for forming bridges: a blow-up at the first bridge."""
    small_scene()
    next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper)).timeStepUpdateInterval = interval
    message = run_error(3)
    assert 'ViscBridgeTimeStepper.timeStepUpdateInterval=%d is out of range; allowed: 1 (' % interval in message
    assert 'maxInterval' in message


def test_a_replaced_interaction_loop_is_checked_again(run_error):
    """Swapping the InteractionLoop for one with another Ip2 after the first steps (same number of
    engines) is caught before YADE's interaction loop would exit() on it."""
    small_scene()
    O.run(3, True)
    idx = [type(e) for e in O.engines].index(yw.InteractionLoop)
    loop = O.engines[idx]
    engines = list(O.engines)
    engines[idx] = yw.InteractionLoop(list(loop.geomDispatcher.functors), [yw.Ip2_FrictMat_FrictMat_MindlinPhys()],
                                      list(loop.lawDispatcher.functors))
    O.engines = engines
    assert 'needs Ip2_FrictMat_FrictMat_ViscBridgePhys' in run_error(3)


@pytest.mark.parametrize('kw,name', [
    (dict(viscosity='1'), 'viscosity'), (dict(normalModel=None), 'normalModel'), (dict(sMin=[1]), 'sMin'),
    (dict(viscosity=True), 'viscosity'), (dict(guard='no'), 'guard'), (dict(timeStepper=1), 'timeStepper'),
    (dict(safety='0.5'), 'safety'), (dict(gravity=(0, 0, '9.81')), 'gravity'), (dict(label_prefix=3), 'label_prefix'),
])
def test_engines_wrong_types_name_the_parameter(kw, name):
    with pytest.raises(ValueError, match=name):
        viscbridge.engines(**kw)


def test_implicit_washino_is_refused_when_the_engines_are_built():
    with pytest.raises(ValueError, match="tangentialModel='washino'.*not dissipative"):
        viscbridge.engines(integration='implicit', tangentialModel='washino')


@pytest.mark.parametrize('kw,name', [
    (dict(initialSpeed=float('nan')), 'initialSpeed'), (dict(n=2.5), 'n'), (dict(n=True), 'n'), (dict(radius='1e-3'), 'radius'),
    (dict(periodic='yes'), 'periodic'), (dict(seed=1.5), 'seed'), (dict(integration='rk4'), 'integration'),
    (dict(cloudFraction=0.5), 'cloudFraction'), (dict(width=float('inf')), 'width'),
])
def test_settling_wrong_values_name_the_parameter(kw, name):
    with pytest.raises(ValueError, match=name):
        scenes.settling(**dict(dict(n=20), **kw))


@pytest.mark.parametrize('args,kw,name', [
    ((0.5e-3, 2500, 1e7, 0.3, '1'), {}, 'viscosity'), ((0.5e-3, 2500, 1e7, 0.3, True), {}, 'viscosity'),
    (('0.5e-3', 2500, 1e7, 0.3, 1.0), {}, 'radius'), ((0.5e-3, 2500, 1e7, 0.3, 1.0), dict(coordination='6'), 'coordination'),
])
def test_criteria_wrong_types_name_the_parameter(args, kw, name):
    from viscbridge import criteria
    with pytest.raises(ValueError, match=name):
        criteria.critical_dt(*args, **kw)


def test_a_scalar_gravity_is_reported_with_the_value_given():
    with pytest.raises(ValueError, match=r"engines: gravity=9\.81 is out of range; allowed: three finite numbers"):
        viscbridge.engines(gravity=9.81)


@pytest.mark.parametrize('kw,message', [
    (dict(s_min_rel=-1), 's_min_rel=-1 is out of range'), (dict(s_min_rel=5), 's_min_rel=5 is out of range'),
    (dict(spring=-5), 'spring=-5 is out of range'), (dict(spring='a'), "spring='a' is out of range"),
    (dict(q_points=0), 'q_points=0 is out of range'), (dict(q_points=2.5), 'q_points=2.5 is out of range'),
    (dict(normal_model='pitois', bridge_volume=-1), 'bridge_volume=-1 is out of range'),
])
def test_lattice_limit_wrong_values_name_the_parameter(kw, message):
    from viscbridge import criteria
    with pytest.raises(ValueError, match=re.escape('lattice_limit: ' + message)):
        criteria.lattice_limit(0.5e-3, 2500, 1.0, 6, **kw)


@pytest.mark.parametrize('args,message', [
    ((2.5e-4, 1.0, 1e-7, 'x'), "normal_model='x' is not a known name"), ((2.5e-4, 1.0, 0.0), 'gap=0.0 is out of range'),
])
def test_normal_coefficient_refuses_an_unknown_model_and_a_zero_gap(args, message):
    """It returned the Adams–Perchard value for any unknown name, and divided by zero at S = 0."""
    from viscbridge import criteria
    with pytest.raises(ValueError, match=re.escape('normal_coefficient: ' + message)):
        criteria.normal_coefficient(*args)
