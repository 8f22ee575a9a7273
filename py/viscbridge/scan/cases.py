"""The cases of a scan: every field a case can set, with its default, unit, meaning and allowed values
(:data:`CASE_DEFAULTS`, :data:`CASE_FIELDS`; the liquid fields' ranges and model names from the C++
registry), checking and normalising a case, its key (what resuming compares), and the sets of cases
a scan runs (one field at a time, or a grid).  Plain Python.
"""
import collections
import hashlib
import itertools
import json
import math
import numbers
import sys

from .. import _registry

__all__ = ['CASE_DEFAULTS', 'CASE_FIELDS', 'Field', 'Interval', 'normalize_case', 'case_key', 'unique_cases',
           'one_at_a_time', 'grid']

#: Every field a case can set, with its default.  Liquid/model fields go to
#: Ip2_FrictMat_FrictMat_ViscBridgePhys; the rest describe the bed and the trial.
CASE_DEFAULTS = dict(
    n=300, radius=0.5e-3, sizeRatio=1.0, density=2500.0, young=1e7, poisson=0.3, friction=0.5, seed=5,
    viscosity=1.0, sMinRel=1e-3, bridgeVolumeRel=0.01, contactAngle=0.0,
    normalModel='adamsPerchard', tangentialModel='slip', en=1.0, integration='explicit',
    steps=2000, perturbation=0.01, tolerance=0.02, capillaryModel='none', surfaceTension=0.0, verdict='energy',
    accuracy=0.0,
)
_LIQUID_KEYS = ('viscosity', 'sMinRel', 'bridgeVolumeRel', 'contactAngle', 'normalModel', 'tangentialModel', 'en',
                'capillaryModel', 'surfaceTension')
# Fields added after scans were run: left out of a case's key while at their default, so that
# those scans still resume.
_KEY_OMITS_AT_DEFAULT = ('capillaryModel', 'surfaceTension', 'verdict', 'accuracy')
_BED_KEYS = ('n', 'radius', 'sizeRatio', 'density', 'young', 'poisson', 'friction', 'seed')


class Interval(collections.namedtuple('Interval', 'lo hi lo_open hi_open')):
    """The allowed values of a numeric field: from lo to hi (None: unbounded), each end open or closed."""

    def __new__(cls, lo=None, hi=None, lo_open=False, hi_open=False):
        return super().__new__(cls, lo, hi, lo_open, hi_open)

    def __contains__(self, x):
        above = self.lo is None or (x > self.lo if self.lo_open else x >= self.lo)
        below = self.hi is None or (x < self.hi if self.hi_open else x <= self.hi)
        return above and below

    def __str__(self):
        if self.lo is None and self.hi is None:
            return 'any'
        if self.hi is None:
            return '%s %.6g' % ('>' if self.lo_open else '>=', self.lo)
        return 'in %s%.6g, %.6g%s' % ('(' if self.lo_open else '[', self.lo, self.hi, ')' if self.hi_open else ']')


Field = collections.namedtuple('Field', 'unit meaning allowed')


def _ip2_range(name):
    """The allowed values of an Ip2 parameter, as the C++ table has them (_registry.PARAMETERS)."""
    p = _registry.PARAMETERS[name]
    return Interval(p['lo'], p['hi'] if math.isfinite(p['hi']) else None, p['lo_open'], p['hi_open'])


def _ip2_models(slot):
    return _registry.SLOTS[slot]['models']


#: Unit, meaning and allowed values of every field of CASE_DEFAULTS (allowed: an Interval, or the
#: names the C++ Ip2 accepts): what ``--help`` lists and :func:`normalize_case` checks.  The liquid
#: ranges are those of Ip2_FrictMat_FrictMat_ViscBridgePhys, the bed ranges those of scenes.settling.
CASE_FIELDS = dict(
    n=Field('', 'number of spheres', Interval(1)),
    radius=Field('m', 'mean sphere radius', Interval(0, lo_open=True)),
    sizeRatio=Field('', 'max/min radius of the uniform radius distribution', Interval(1, 5)),
    density=Field('kg/m³', 'solid density', Interval(0, lo_open=True)),
    young=Field('Pa', "Young's modulus", Interval(0, lo_open=True)),
    poisson=Field('', "Poisson's ratio", Interval(-1, 0.5, True, True)),
    friction=Field('rad', 'friction angle', Interval(0)),
    seed=Field('', 'random seed of the bed and of the perturbation', Interval()),
    viscosity=Field('Pa·s', 'liquid viscosity (0: dry)', _ip2_range('viscosity')),
    sMinRel=Field('', 'minimum gap S_min over the reduced radius', _ip2_range('sMinRel')),
    bridgeVolumeRel=Field('', 'bridge volume over the mean particle volume', _ip2_range('bridgeVolumeRel')),
    contactAngle=Field('rad', 'contact angle', _ip2_range('contactAngle')),
    normalModel=Field('', 'normal viscous force', _ip2_models('normalModel')),
    tangentialModel=Field('', 'tangential viscous force', _ip2_models('tangentialModel')),
    en=Field('', 'restitution coefficient of the dry contact', _ip2_range('en')),
    capillaryModel=Field('', 'capillary force of the bridges', _ip2_models('capillaryModel')),
    surfaceTension=Field('N/m', 'surface tension (0: no capillary force)', _ip2_range('surfaceTension')),
    integration=Field('', 'time integration of the viscous forces', _registry.INTEGRATIONS),
    steps=Field('', 'steps of each trial at a fixed time step', Interval(1)),
    perturbation=Field('m/s', 'amplitude of the random initial velocities', Interval(0)),
    tolerance=Field('', 'bisection stops at dt_unstable/dt_stable <= 1 + tolerance', Interval(0, lo_open=True)),
    verdict=Field('', "instability criterion: 'energy' (kinetic above released potential energy) or 'period2' "
                      "(that, or a ringing at the step's frequency: consecutive velocities anti-correlated, "
                      "which the energy criterion misses in the transition and collision regimes)", ('energy', 'period2')),
    accuracy=Field('', "with a tolerance (0: none), the case also runs the trial's time (steps at the largest stable Δt) with "
                       "ViscBridgeTimeStepper.accuracy at it and integration 'auto', and reports its steps, engine time, "
                       "scheme switches and estimated error (accuracy_* columns)", Interval(0, 1, False, True)),
)


def _describe(case):
    """The fields of a case that differ from the defaults, as FIELD=VALUE."""
    changed = ['%s=%r' % (k, v) for k, v in case.items() if v != CASE_DEFAULTS[k]]
    return ' '.join(changed) or '(defaults)'


def _check_known(fields):
    unknown = set(fields) - set(CASE_DEFAULTS)
    if unknown:
        raise ValueError('scan case: unknown field(s) %s; allowed: %s' % (', '.join(sorted(unknown)), ', '.join(CASE_DEFAULTS)))


def _number(value, kind):
    """value as a plain `kind` (int or float), or None when it is not a finite number of that kind
    (numpy scalars are numbers; bool and str are not)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return None
    try:
        x = float(value)
    except OverflowError:
        return None
    if not math.isfinite(x):
        return None
    if kind is int:
        return int(value) if x == int(x) else None
    return x


def _allowed(name):
    """What field `name` accepts, in words (without the unit)."""
    allowed = CASE_FIELDS[name].allowed
    if not isinstance(allowed, Interval):
        return ', '.join(repr(a) for a in allowed)
    kind = 'an integer' if isinstance(CASE_DEFAULTS[name], int) else 'a number'
    return kind if allowed == Interval() else '%s %s' % (kind, allowed)


def _checked(name, value):
    """value of field `name` converted to its default's type (so that 1 and 1.0 are one case), or ValueError."""
    field = CASE_FIELDS[name]
    if isinstance(field.allowed, Interval):
        x = _number(value, type(CASE_DEFAULTS[name]))
        if x is not None and x in field.allowed:
            return x
    elif isinstance(value, str) and value in field.allowed:
        return value
    unit = ' [%s]' % field.unit if field.unit else ''
    raise ValueError('scan case: %s=%r is out of range; allowed: %s%s' % (name, value, _allowed(name), unit))


def _check_with_ip2(case):
    """Inside YADE the C++ functor has the last word on the liquid fields (ValueError naming the
    field).  YADE is not imported for this: the driver of a scan runs in plain Python."""
    wrapper = sys.modules.get('yade.wrapper')
    ip2 = getattr(wrapper, 'Ip2_FrictMat_FrictMat_ViscBridgePhys', None)
    if ip2 is not None:
        ip2(**{k: case[k] for k in _LIQUID_KEYS})


def normalize_case(case):
    """The case with defaults filled in and every value of its default's type; ValueError naming
    the field on unknown fields and on values out of range."""
    _check_known(case)
    out = {name: _checked(name, value) for name, value in dict(CASE_DEFAULTS, **case).items()}
    _check_with_ip2(out)
    return out


def case_key(case):
    """A stable identifier of a (normalized) case: what resuming compares."""
    c = normalize_case(case)
    text = json.dumps({k: v for k, v in c.items() if not (k in _KEY_OMITS_AT_DEFAULT and v == CASE_DEFAULTS[k])}, sort_keys=True)
    return hashlib.sha1(text.encode()).hexdigest()[:16]


def unique_cases(cases):
    """The cases normalized, each once (the first of equal ones, in order)."""
    out = {}
    for c in cases:
        c = normalize_case(c)
        out.setdefault(case_key(c), c)
    return list(out.values())


def one_at_a_time(base, **variations):
    """The base case, then each listed value of each field with the others at the base values."""
    _check_known(variations)
    base = normalize_case(base)
    return unique_cases([base] + [dict(base, **{field: v}) for field, values in variations.items() for v in values])


def grid(base=None, **axes):
    """The cartesian product of the listed values (other fields from `base`)."""
    _check_known(axes)
    base = normalize_case(base or {})
    names = list(axes)
    return unique_cases(dict(base, **dict(zip(names, values))) for values in itertools.product(*(axes[n] for n in names)))
