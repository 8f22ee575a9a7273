"""The cases of a scan: every field a case can set, with its default, unit, meaning and allowed values
(:data:`CASE_DEFAULTS`, :data:`CASE_FIELDS`; the liquid fields' ranges and model names from the C++
registry), checking and normalising a case, its key (what resuming compares), and the sets of cases
a scan runs (one field at a time, or a grid).  Plain Python.

A case is of one of the :data:`KINDS`: 'settling' (the critical Δt of a wetted bed; a case without a
``kind`` field is one, as every case was before drums) or 'drum' (a granulation drum turned for some
revolutions, :data:`DRUM_DEFAULTS`, :data:`DRUM_FIELDS`; its case carries ``kind='drum'``).
"""
import collections
import hashlib
import itertools
import json
import math
import numbers
import sys

from .. import _registry

__all__ = ['CASE_DEFAULTS', 'CASE_FIELDS', 'DRUM_DEFAULTS', 'DRUM_FIELDS', 'DRUM_SPRAY_KEYS', 'KINDS', 'Kind', 'Field', 'Interval',
           'kind_of', 'normalize_case', 'case_key', 'unique_cases', 'one_at_a_time', 'grid']

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
"""A field of a case: its unit ('' for a number without unit or a name), its meaning, and the values
it allows (an :class:`Interval`, or a tuple of names), as ``--help`` lists them."""


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


#: Every field of a drum case (kind='drum'), with its default: the parameters of
#: :func:`viscbridge.scenes.drum` (its defaults, except the size: 300 spheres in a 15 mm drum) and the
#: revolutions it turns.  A case's result holds the final agglomerate measures (scan/drum_trial.py).
DRUM_DEFAULTS = dict(
    n=300, radius=1e-3, drumRadius=15e-3, length=10e-3, density=2500.0, young=1e7, poisson=0.3, friction=0.5,
    wallFriction=0.8, segments=32, seed=1, froude=0.05, rpm=0.0, viscosity=1.0, liquidModel='film', wetFraction=0.15,
    filmRel=0.02, minBridgeRel=0.002, bridgeVolumeRel=0.01, integration='implicit', revolutions=1.0,
    sprayRel=0.0, sprayRevolutions=1.0, sprayStart=0.0, sprayDropletRel=0.0,
)
# Fields added to drum cases after drum scans were run: left out of a case's key while at their default.
_DRUM_KEY_OMITS_AT_DEFAULT = ('sprayRel', 'sprayRevolutions', 'sprayStart', 'sprayDropletRel')
#: The fields that describe the spray, not the drum: each one's argument of Drum.spray.
DRUM_SPRAY_KEYS = dict(sprayRel='volumeRel', sprayRevolutions='revolutions', sprayStart='start', sprayDropletRel='dropletRel')
_DRUM_LIQUID_KEYS = ('viscosity', 'bridgeVolumeRel')

#: Unit, meaning and allowed values of every field of DRUM_DEFAULTS (the ranges scenes.drum accepts).
DRUM_FIELDS = dict(
    n=Field('', 'number of spheres', Interval(1)),
    radius=Field('m', 'sphere radius (each sphere up to 10 % smaller)', Interval(0, lo_open=True)),
    drumRadius=Field('m', 'inner radius of the drum (at least 5 sphere radii)', Interval(0, lo_open=True)),
    length=Field('m', 'length of the drum between its flat end walls (at least 4 sphere radii)', Interval(0, lo_open=True)),
    density=CASE_FIELDS['density'],
    young=CASE_FIELDS['young'],
    poisson=CASE_FIELDS['poisson'],
    friction=Field('rad', 'friction angle between spheres', Interval(0)),
    wallFriction=Field('rad', 'friction angle of the drum wall', Interval(0, math.pi / 2)),
    segments=Field('', 'facet segments around the drum (two triangles each)', Interval(8)),
    seed=Field('', 'random seed of the bed and of the wetted spheres', Interval()),
    froude=Field('', 'drum speed as the Froude number ω²R/g (used when rpm is 0)', Interval(0, 1, lo_open=True)),
    rpm=Field('1/min', 'drum speed in revolutions per minute; 0: set by froude', Interval(0)),
    viscosity=Field('Pa·s', 'binder viscosity (0: dry)', _ip2_range('viscosity')),
    liquidModel=Field('', "'film': conserved liquid taken from the wetted spheres' films; 'fixed': every contact a "
                          "bridge", ('film', 'fixed')),
    wetFraction=Field('', "fraction of the spheres that carry a film (liquidModel 'film')", Interval(0, 1)),
    filmRel=Field('', 'film of a wetted sphere over its volume', Interval(0, 1)),
    minBridgeRel=Field('', 'the least liquid a bridge forms from, over a sphere volume', Interval(0, 1)),
    bridgeVolumeRel=Field('', 'largest bridge volume over the mean particle volume', _ip2_range('bridgeVolumeRel')),
    integration=Field('', 'time integration of the viscous forces', _registry.INTEGRATIONS),
    revolutions=Field('', 'revolutions the drum turns', Interval(0, lo_open=True)),
    sprayRel=Field('', "binder sprayed onto the bed's surface as the drum turns, over the particles' volume (0: no spray; "
                       "needs liquidModel 'film'; Drum.spray)", Interval(0, 1)),
    sprayRevolutions=Field('', 'revolutions the spray lasts (its rate: sprayRel of the particles\' volume over them)',
                           Interval(0, lo_open=True)),
    sprayStart=Field('', 'revolution at which the spray starts', Interval(0)),
    sprayDropletRel=Field('', "the spray's droplet volume over a mean particle's volume (0: a fine mist over the whole "
                              "reached surface)", Interval(0, 1)),
)


class Kind(collections.namedtuple('Kind', 'defaults fields key_omits_at_default liquid_keys meaning')):
    """A kind of case: its fields' defaults and descriptions, the fields left out of its key at their
    default, the fields the C++ Ip2 checks, and what its cases do (for --help)."""


#: The kinds of case, by the value of a case's ``kind`` field (absent: 'settling').
KINDS = dict(
    settling=Kind(CASE_DEFAULTS, CASE_FIELDS, _KEY_OMITS_AT_DEFAULT, _LIQUID_KEYS,
                  'the critical time step of a wetted bed, by bisection (results: dt_critical, ...)'),
    drum=Kind(DRUM_DEFAULTS, DRUM_FIELDS, _DRUM_KEY_OMITS_AT_DEFAULT, _DRUM_LIQUID_KEYS,
              'a granulation drum (viscbridge.scenes.drum) turned for `revolutions` (results: the final agglomerates, '
              'granules, granulated_mass_fraction, granule_d50, largest, coordination, liquid_cov, ...)'),
)


def kind_of(case):
    """The kind of a case: its ``kind`` field, 'settling' without one; ValueError for an unknown kind."""
    kind = case.get('kind', 'settling')
    if not isinstance(kind, str) or kind not in KINDS:
        raise ValueError('scan case: kind=%r is not a known kind; allowed: %s' % (kind, ', '.join(repr(k) for k in KINDS)))
    return kind


def _describe(case):
    """The fields of a case that differ from the defaults of its kind, as FIELD=VALUE."""
    defaults = KINDS[kind_of(case)].defaults
    changed = ['%s=%r' % (k, v) for k, v in case.items() if k not in defaults or v != defaults[k]]
    return ' '.join(changed) or '(defaults)'


def _check_known(fields, kind='settling'):
    defaults = KINDS[kind].defaults
    unknown = set(fields) - set(defaults) - {'kind'}
    if unknown:
        raise ValueError('scan case: unknown field(s) %s%s; allowed: %s' % (
            ', '.join(sorted(unknown)), '' if kind == 'settling' else ' of a %s case' % kind, ', '.join(defaults)))


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


def _allowed(name, kind='settling'):
    """What field `name` of a case of `kind` accepts, in words (without the unit)."""
    spec = KINDS[kind]
    allowed = spec.fields[name].allowed
    if not isinstance(allowed, Interval):
        return ', '.join(repr(a) for a in allowed)
    what = 'an integer' if isinstance(spec.defaults[name], int) else 'a number'
    return what if allowed == Interval() else '%s %s' % (what, allowed)


def _checked(name, value, kind='settling'):
    """value of field `name` converted to its default's type (so that 1 and 1.0 are one case), or ValueError."""
    spec = KINDS[kind]
    field = spec.fields[name]
    if isinstance(field.allowed, Interval):
        x = _number(value, type(spec.defaults[name]))
        if x is not None and x in field.allowed:
            return x
    elif isinstance(value, str) and value in field.allowed:
        return value
    unit = ' [%s]' % field.unit if field.unit else ''
    raise ValueError('scan case: %s=%r is out of range; allowed: %s%s' % (name, value, _allowed(name, kind), unit))


def _check_drum(case):
    """What scenes.drum checks between fields, before anything runs (ValueError naming the fields)."""
    if case['drumRadius'] < 5 * case['radius'] or case['length'] < 4 * case['radius']:
        raise ValueError('scan case: drumRadius=%r and length=%r [m] are out of range; allowed: at least 5 and 4 sphere '
                         'radii (radius=%r m)' % (case['drumRadius'], case['length'], case['radius']))
    if case['rpm'] > 0 and case['froude'] != DRUM_DEFAULTS['froude']:
        raise ValueError('scan case: froude=%r and rpm=%r both set the drum speed; allowed: one of them (rpm=0 for froude)'
                         % (case['froude'], case['rpm']))
    if case['sprayRel'] > 0 and case['liquidModel'] != 'film':
        raise ValueError("scan case: sprayRel=%r needs liquidModel='film' (sprayed binder goes into the films), not %r"
                         % (case['sprayRel'], case['liquidModel']))


def _check_with_ip2(case):
    """Inside YADE the C++ functor has the last word on the liquid fields (ValueError naming the
    field).  YADE is not imported for this: the driver of a scan runs in plain Python."""
    wrapper = sys.modules.get('yade.wrapper')
    ip2 = getattr(wrapper, 'Ip2_FrictMat_FrictMat_ViscBridgePhys', None)
    if ip2 is not None:
        ip2(**{k: case[k] for k in KINDS[kind_of(case)].liquid_keys})


def normalize_case(case):
    """The case with the defaults of its kind filled in and every value of its default's type;
    ValueError naming the field on unknown fields and on values out of range.  A settling case has
    no ``kind`` field (as before drums), a drum case has kind='drum'."""
    kind = kind_of(case)
    spec = KINDS[kind]
    fields = {k: v for k, v in case.items() if k != 'kind'}
    _check_known(fields, kind)
    out = {name: _checked(name, value, kind) for name, value in dict(spec.defaults, **fields).items()}
    if kind == 'drum':
        out = dict(kind=kind, **out)
        _check_drum(out)
    _check_with_ip2(out)
    return out


def case_key(case):
    """A stable identifier of a (normalized) case: what resuming compares."""
    c = normalize_case(case)
    spec = KINDS[kind_of(c)]
    kept = {k: v for k, v in c.items() if not (k in spec.key_omits_at_default and v == spec.defaults[k])}
    return hashlib.sha1(json.dumps(kept, sort_keys=True).encode()).hexdigest()[:16]


def unique_cases(cases):
    """The cases normalized, each once (the first of equal ones, in order)."""
    out = {}
    for c in cases:
        c = normalize_case(c)
        out.setdefault(case_key(c), c)
    return list(out.values())


def _axes_of(base, variations):
    """The kind of `base` and `variations` checked against its fields (the kind itself cannot vary)."""
    kind = kind_of(base)
    if 'kind' in variations:
        raise ValueError('scan case: kind cannot be varied; a scan runs cases of one kind (--kind)')
    _check_known(variations, kind)
    return kind


def one_at_a_time(base, **variations):
    """The base case, then each listed value of each field with the others at the base values."""
    _axes_of(base, variations)
    base = normalize_case(base)
    return unique_cases([base] + [dict(base, **{field: v}) for field, values in variations.items() for v in values])


def grid(base=None, **axes):
    """The cartesian product of the listed values (other fields from `base`)."""
    _axes_of(base or {}, axes)
    base = normalize_case(base or {})
    names = list(axes)
    return unique_cases(dict(base, **dict(zip(names, values))) for values in itertools.product(*(axes[n] for n in names)))
