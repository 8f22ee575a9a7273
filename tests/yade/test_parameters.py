"""Every user-settable parameter of every ViscBridge class and function inside YADE: bad input is a
Python exception naming the parameter, its value and the allowed range — on assignment (the previous
valid value stays in place), or at the latest at the first step — and the Ip2 accepts exactly the
models and ranges the registry (_registry.py) lists.  (The plain-Python functions' checks:
tests/unit/test_criteria.py, tests/unit/test_scan.py.)"""
import math
import re

import pytest
from yade import O, utils
import yade.wrapper as yw
from yade.wrapper import Ip2_FrictMat_FrictMat_ViscBridgePhys, Law2_ScGeom_ViscBridgePhys_HertzViscous

import viscbridge
import viscbridge.scenes as scenes
from viscbridge import _registry
from viscbridge.engine_list import ip2_defaults
from wetpairs import R, material

ATTRIBUTES = [
    (yw.Law2_ScGeom_ViscBridgePhys_HertzViscous, 'integration', 'semi', "'explicit', 'implicit'"),
    (yw.ViscBridgeTimeStepper, 'safety', 0.0, '(0, 1]'),
    (yw.ViscBridgeTimeStepper, 'safety', 1.5, '(0, 1]'),
    (yw.ViscBridgeTimeStepper, 'maxGrowth', 0.5, '[1,'),
    (yw.ViscBridgeTimeStepper, 'rayleighFraction', 0.0, '(0, 1]'),
    (yw.ViscBridgeTimeStepper, 'maxDt', -1e-6, '>= 0'),
    (yw.ViscBridgeTimeStepper, 'errorFilterInterval', 0, '[1,'),
    (yw.ViscBridgeImplicitSolver, 'tolerance', 0.0, '(0, 1)'),
    (yw.ViscBridgeImplicitSolver, 'tolerance', 1.0, '(0, 1)'),
    (yw.ViscBridgeImplicitSolver, 'maxIterations', 0, '[1,'),
    (yw.ViscBridgeImplicitSolver, 'refreshIterations', 0, '[1,'),
    (yw.ViscBridgeImplicitSolver, 'preconditioner', 'ilu', "'cholesky', 'multigrid', 'jacobi', 'auto'"),
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


WRONG_TYPES = [
    (yw.Ip2_FrictMat_FrictMat_ViscBridgePhys, 'viscosity', '10', 'a number'),
    (yw.Ip2_FrictMat_FrictMat_ViscBridgePhys, 'normalModel', 3, 'str'),
    (yw.ViscBridgeTimeStepper, 'safety', [0.5], 'a number'),
    (yw.ViscBridgeLiquid, 'minBridgeVolume', None, 'a number'),
]


@pytest.mark.parametrize('cls,name,value,expected', WRONG_TYPES, ids=lambda x: getattr(x, '__name__', str(x)))
def test_a_wrong_type_names_the_attribute(cls, name, value, expected):
    """Not Boost's "did not match C++ signature" / "No registered converter": the class, the
    attribute, the value and what it takes (viscbridge/_attribute_types.py, installed on import)."""
    obj = cls()
    before = getattr(obj, name)
    for attempt in (lambda: setattr(obj, name, value), lambda: cls(**{name: value})):
        with pytest.raises(TypeError) as err:
            attempt()
        message = str(err.value)
        assert message.startswith('%s.%s=%r has the wrong type' % (cls.__name__, name, value)) and 'expected ' + expected in message, message
    assert getattr(obj, name) == before
    assert getattr(cls(**{name: before}), name) == before  # the right type still passes


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


def test_a_time_step_update_interval_of_0_is_an_error(run_error):
    """0 would divide by zero in YADE's TimeStepper."""
    small_scene()
    next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper)).timeStepUpdateInterval = 0
    message = run_error(3)
    assert 'ViscBridgeTimeStepper.timeStepUpdateInterval=0 is out of range; allowed: >= 1' in message


def test_a_time_step_update_interval_caps_the_full_updates_and_bridges_are_still_corrected():
    """timeStepUpdateInterval=10 (what GlobalStiffnessTimeStepper scripts set) is accepted with the
    meaning a YADE user expects: at most 10 steps between full updates; the stepper still runs every
    step, so a forming bridge is corrected at once (skipping steps once blew up at the first bridge)."""
    small_scene()
    stepper = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
    stepper.timeStepUpdateInterval = 10
    intervals = []
    for _ in range(300):
        O.run(10, True)
        intervals.append(stepper.updateInterval)
    assert max(intervals) <= 10 and stepper.updates >= 300 * 10 // 10 - 5
    assert any(i.phys.bridge for i in O.interactions if i.isReal)
    assert all(math.isfinite(v) for b in O.bodies for v in b.state.vel)


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


def test_a_scalar_gravity_is_reported_with_the_value_given():
    with pytest.raises(ValueError, match=r"engines: gravity=9\.81 is out of range; allowed: three finite numbers"):
        viscbridge.engines(gravity=9.81)


# --- Ip2_FrictMat_FrictMat_ViscBridgePhys ------------------------------------------------------------
IP2_BAD = [
    ('viscosity', -1.0, '>= 0'),
    ('viscosity', float('nan'), '>= 0'),
    ('bridgeVolume', -1e-12, '>= 0'),
    ('bridgeVolumeRel', 0.0, '(0, 1]'),
    ('contactAngle', 2.0, '[0, 1.570796327]'),
    ('contactAngle', -0.1, '[0, 1.570796327]'),
    ('sMin', -1e-9, '>= 0'),
    ('sMinRel', 0.0, '(0, 1]'),
    ('sMinRel', 2.0, '(0, 1]'),
    ('formationDistance', -1e-6, '>= 0'),
    ('en', 0.0, '(0, 1]'),
    ('en', 1.5, '(0, 1]'),
    ('normalModel', 'stokes', "'none', 'adamsPerchard', 'pitois'"),
    ('tangentialModel', 'Goldman', "'none', 'washino', 'slip', 'goldman'"),
]


@pytest.mark.parametrize('name,value,allowed', IP2_BAD)
def test_ip2_rejects_on_assignment_and_keeps_previous_value(name, value, allowed):
    ip2 = Ip2_FrictMat_FrictMat_ViscBridgePhys()
    before = getattr(ip2, name)
    with pytest.raises(ValueError) as err:
        setattr(ip2, name, value)
    msg = str(err.value)
    shown = ('%g' % value) if isinstance(value, float) else "'%s'" % value
    assert name in msg and allowed in msg and shown in msg, msg
    assert getattr(ip2, name) == before or (isinstance(before, float) and math.isnan(before))


@pytest.mark.parametrize('name,value,allowed', IP2_BAD)
def test_ip2_constructor_rejects(name, value, allowed):
    with pytest.raises(ValueError, match=name):
        Ip2_FrictMat_FrictMat_ViscBridgePhys(**{name: value})


def test_ip2_accepts_valid_values():
    ip2 = Ip2_FrictMat_FrictMat_ViscBridgePhys(viscosity=100.0, bridgeVolume=1e-12, contactAngle=math.pi / 2,
                                               sMin=1e-8, normalModel='pitois', tangentialModel='goldman', en=0.5)
    assert (ip2.viscosity, ip2.normalModel, ip2.tangentialModel, ip2.en) == (100.0, 'pitois', 'goldman', 0.5)


def test_law_integration_names():
    law = Law2_ScGeom_ViscBridgePhys_HertzViscous()
    assert law.integration == 'explicit'
    with pytest.raises(ValueError, match="integration='semi'.*'explicit'"):
        law.integration = 'semi'
    assert law.integration == 'explicit'


def test_engines_rejects_unknown_effects():
    with pytest.raises(ValueError, match='viscosityy'):
        viscbridge.engines(viscosityy=1.0)
    with pytest.raises(ValueError, match='tangentialModel'):
        viscbridge.engines(viscosity=1.0, tangentialModel='sticky')


# --- what the registry lists is what the Ip2 accepts -----------------------------------------------
@pytest.mark.parametrize('slot', ['normalModel', 'tangentialModel', 'capillaryModel'])
def test_every_listed_model_is_accepted_and_nothing_else(slot):
    ip2 = yw.Ip2_FrictMat_FrictMat_ViscBridgePhys()
    assert getattr(ip2, slot) == _registry.SLOTS[slot]['default']
    for name in _registry.SLOTS[slot]['models']:
        setattr(ip2, slot, name)
        assert getattr(ip2, slot) == name
    with pytest.raises(ValueError, match=slot):
        setattr(ip2, slot, 'notAModel')


def test_parameter_defaults_and_ranges_are_the_ip2s():
    ip2 = yw.Ip2_FrictMat_FrictMat_ViscBridgePhys()
    assert set(_registry.PARAMETERS) <= set(ip2_defaults())
    for name, spec in _registry.PARAMETERS.items():
        assert getattr(ip2, name) == spec['default'], name
        below = spec['lo'] - 1.0 if not spec['lo_open'] else spec['lo']
        with pytest.raises(ValueError, match=name):
            setattr(ip2, name, below)
