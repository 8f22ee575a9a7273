"""viscbridge.scan inside YADE: the trial's instability verdicts on a wetted bed, and the case fields'
ranges and model names against what the C++ Ip2 accepts."""
import math

import pytest

import viscbridge.criteria as criteria
import viscbridge.scan as scan

pytestmark = pytest.mark.slow  # a dry bed is settled and wetted trials run

TINY = dict(n=40, steps=300, tolerance=0.2, seed=2)


@pytest.fixture(scope='module')
def bed_dir(tmp_path_factory):
    return str(tmp_path_factory.mktemp('beds'))


def test_criterion_classifies_known_runs(bed_dir):
    """Wetted bed: stable at half the time stepper's step, unstable at 3× the pair limit 2 t_v."""
    case = scan.normalize_case(dict(TINY, viscosity=10.0))
    trial = scan._Trial(case, scan.dry_bed(case, bed_dir))
    dt_stepper = trial.stepper_dt()['dt_stepper']
    assert trial.unstable_at(0.5 * dt_stepper) is None
    t_v = 4.0 / 9.0 * 2500 * 0.5e-3 * (1e-3 * 0.25e-3) / 10.0
    why = trial.unstable_at(3 * 2 * t_v)
    assert why and ('exceeds' in why or 'non-finite' in why)


def test_allowed_values_are_those_of_the_ip2():
    """Model names come from viscbridge.criteria (as ModelNames.hpp); the liquid ranges agree with
    what the C++ functor accepts, probed at and around their ends."""
    import yade.wrapper as yw
    assert scan.CASE_FIELDS['normalModel'].allowed is criteria.NORMAL_MODELS
    assert scan.CASE_FIELDS['tangentialModel'].allowed is criteria.TANGENTIAL_MODELS
    assert scan.CASE_FIELDS['integration'].allowed is criteria.INTEGRATIONS
    assert set(scan.CASE_FIELDS) == set(scan.CASE_DEFAULTS)

    def ip2_accepts(**kw):
        try:
            yw.Ip2_FrictMat_FrictMat_ViscBridgePhys(**kw)
            return True
        except ValueError:
            return False
    for field in ('normalModel', 'tangentialModel'):
        for name in scan.CASE_FIELDS[field].allowed + ('foo',):
            assert ip2_accepts(**{field: name}) == (name in scan.CASE_FIELDS[field].allowed)
    for field in ('viscosity', 'sMinRel', 'bridgeVolumeRel', 'contactAngle', 'en'):
        for v in (-1.0, 0.0, 1e-9, 0.5, 1.0, 1.5, math.pi / 2, math.pi / 2 + 1e-9, 2.0):
            assert ip2_accepts(**{field: v}) == (v in scan.CASE_FIELDS[field].allowed), (field, v)


def test_a_case_with_a_tolerance_reports_the_accuracy_run(bed_dir):
    """accuracy=1e-2: after the bisection, the trial's time runs with the tolerance; at 100 Pa·s the
    stepper goes implicit and needs fewer steps than the fixed-Δt trial at its stable step, with an
    estimate within the tolerance (its first step at 1 % of tol × the limit, physics.md A4: starting
    at tol × the limit, 32 steps ended at 5× the tolerance)."""
    r = scan.find_critical_dt(dict(TINY, viscosity=100.0, accuracy=1e-2), bed_dir)
    assert r['accuracy_scheme'] == 'implicit' and r['accuracy_switches'] >= 1
    assert r['accuracy_unstable'] == ''
    assert 0 < r['accuracy_steps'] < TINY['steps'] / 2, r['accuracy_steps']
    assert 0 < r['accuracy_error_estimate'] <= 1.5e-2 and r['accuracy_seconds'] > 0


def test_drum_fields_are_those_of_scenes_drum():
    """A drum case's defaults and units are scenes.drum's (its size aside: the scan fixes n and the
    drum instead of deriving them from fill), and every argument a case gives it is one it takes."""
    import importlib
    import inspect
    drum_module = importlib.import_module('viscbridge.scenes.drum')  # viscbridge.scenes.drum is the function
    signature = inspect.signature(drum_module.drum).parameters
    spray = inspect.signature(drum_module.Drum.spray).parameters
    for name, default in scan.DRUM_DEFAULTS.items():
        if name in scan.DRUM_SPRAY_KEYS:  # an argument of Drum.spray (sprayRel has no default there: 0 means no spray)
            given = spray[scan.DRUM_SPRAY_KEYS[name]].default
            # Drum.spray's start None is now: 0 for a drum just built, as a scan's case is
            assert given in (default, inspect.Parameter.empty) or (name, given, default) == ('sprayStart', None, 0.0), name
            continue
        assert scan.DRUM_FIELDS[name].unit == drum_module.UNITS.get(name, ''), name
        if name == 'integration':  # scenes.drum: None, 'implicit' unless accuracy is asked for
            assert signature[name].default is None and default == 'implicit'
        elif name == 'froude':  # scenes.drum: None, 0.05 unless rpm is given
            assert signature[name].default is None and default == 0.05
        elif name not in ('n', 'drumRadius', 'length', 'rpm', 'revolutions', 'bridgeVolumeRel'):
            assert signature[name].default == default, name
    import yade.wrapper as yw
    assert scan.DRUM_DEFAULTS['bridgeVolumeRel'] == yw.Ip2_FrictMat_FrictMat_ViscBridgePhys().bridgeVolumeRel
    for case in (dict(kind='drum'), dict(kind='drum', rpm=30)):
        assert set(scan.drum_arguments(case)) <= set(signature) | {'bridgeVolumeRel'}


def test_a_sprayed_drum_case_reports_the_liquid_it_sprayed(tmp_path):
    r = scan.run_drum_case(dict(kind='drum', n=40, drumRadius=8e-3, length=6e-3, wetFraction=0.0, revolutions=0.15,
                                sprayRel=0.01, sprayRevolutions=0.1), str(tmp_path))
    assert r['liquid_sprayed'] > 0 and r['sprayRel'] == 0.01
    particles = 40 * 4 / 3 * math.pi * 1e-9 * 0.9 ** 3  # radii 0.9–1 mm
    assert 0.9 * 0.01 * particles < r['liquid_sprayed'] < 0.01 * particles / 0.9 ** 3 * 1.001
