"""Critical time step of settling cases by bisection, and parameter scans that resume and run in
parallel (yade-batch locally, or as a Slurm array job on a cluster).

The case (one row of a scan): a bed of spheres settled dry in a walled column
(:func:`viscbridge.scenes.settling`), then wetted — every contact becomes a liquid bridge at S_min,
the stiffest viscous state — and released under gravity with small random velocities.  It runs
`steps` steps at a fixed Δt.  **Instability criterion** (:func:`viscbridge.scenes.instability`):
the kinetic energy exceeds the initial kinetic energy plus the potential energy released since the
start, or becomes NaN/inf.  Physics cannot do that; an explicit scheme above its stable step does,
because the unstable mode grows by a factor |1 − Δt/t_v| > 1 per step.

Command line (inside the environment, e.g. ``./yadew sh python3 -m viscbridge.scan ...``)::

    python3 -m viscbridge.scan run    DIR [--vary viscosity=1e-3,1,100] [--base radius=0.5e-3 ...] [-j 2]
    python3 -m viscbridge.scan table  DIR ...same case options...     # only write DIR/cases.table
    python3 -m viscbridge.scan collect DIR                             # DIR/results.csv from results.jsonl
    python3 -m viscbridge.scan slurm  DIR                              # DIR/scan.sbatch for the same table

``--help`` lists the case fields (:data:`CASE_FIELDS`).  Every case is checked before anything
runs; equal cases (``viscosity=1`` and ``viscosity=1.0``) run once.  Every finished case is
appended to ``DIR/results.jsonl`` at once; re-running skips finished cases, so a killed or
interrupted scan resumes where it stopped.  ``DIR/cases.table`` holds the whole scan,
``DIR/todo.table`` the cases yade-batch was given; per-case logs are ``DIR/case-KEY.log``.  Cases
that fail are listed with their error and make the command exit non-zero.
"""
import argparse
import collections
import contextlib
import hashlib
import itertools
import json
import math
import numbers
import os
import re
import signal
import subprocess
import sys
import threading
import time

from . import _registry, criteria

__all__ = ['CASE_DEFAULTS', 'CASE_FIELDS', 'Field', 'Interval', 'ScanError', 'CasesFailed', 'normalize_case',
           'case_key', 'unique_cases', 'one_at_a_time', 'grid', 'bisect_threshold', 'find_critical_dt', 'ResultsFile',
           'write_table', 'run_cases', 'collect', 'slurm_script', 'build_parser', 'main']

#: Every field a case can set, with its default.  Liquid/model fields go to
#: Ip2_FrictMat_FrictMat_ViscBridgePhys; the rest describe the bed and the trial.
CASE_DEFAULTS = dict(
    n=300, radius=0.5e-3, sizeRatio=1.0, density=2500.0, young=1e7, poisson=0.3, friction=0.5, seed=5,
    viscosity=1.0, sMinRel=1e-3, bridgeVolumeRel=0.01, contactAngle=0.0,
    normalModel='adamsPerchard', tangentialModel='slip', en=1.0, integration='explicit',
    steps=2000, perturbation=0.01, tolerance=0.02, capillaryModel='none', surfaceTension=0.0, verdict='energy',
)
_LIQUID_KEYS = ('viscosity', 'sMinRel', 'bridgeVolumeRel', 'contactAngle', 'normalModel', 'tangentialModel', 'en',
                'capillaryModel', 'surfaceTension')
# Fields added after scans were run: left out of a case's key while at their default, so that
# those scans still resume.
_KEY_OMITS_AT_DEFAULT = ('capillaryModel', 'surfaceTension', 'verdict')
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
)


class ScanError(Exception):
    """A scan that cannot go on (missing directory or table, ...): reported as one line."""


class CasesFailed(ScanError):
    """Some cases of a run left no result; `failed` lists (case, error message)."""

    def __init__(self, failed, scan_dir):
        self.failed = failed
        lines = ['%d case(s) failed (logs: %s/case-KEY.log; running the scan again retries them):'
                 % (len(failed), scan_dir)]
        lines += ['  %s %s: %s' % (case_key(c), _describe(c), error) for c, error in failed]
        super().__init__('\n'.join(lines))


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


# ------------------------------------------------------------------------------------------------
# bisection
# ------------------------------------------------------------------------------------------------
def bisect_threshold(is_unstable, lo, hi, tolerance=0.02, max_expand=30):
    """Bracket the smallest unstable value of a monotone stable→unstable predicate, in log space.

    Starts from a guess [lo, hi]; moves lo down (÷2) until stable and hi up (×2) until unstable,
    then bisects until hi/lo ≤ 1 + tolerance.  Returns (lo, hi, trials) with `trials` the list of
    (value, unstable) evaluated, in order.
    """
    if not (0 < lo < hi):
        raise ValueError('bisect_threshold: need 0 < lo < hi, got lo=%r, hi=%r' % (lo, hi))
    if not tolerance > 0:
        raise ValueError('bisect_threshold: tolerance=%r is out of range; allowed: > 0' % (tolerance,))
    trials = []

    def test(x):
        u = bool(is_unstable(x))
        trials.append((x, u))
        return u

    for _ in range(max_expand):
        if not test(lo):
            break
        hi, lo = lo, lo / 2
    else:
        raise RuntimeError('bisect_threshold: no stable value found down to %g' % lo)
    for _ in range(max_expand):
        if test(hi):
            break
        lo, hi = hi, hi * 2
    else:
        raise RuntimeError('bisect_threshold: no unstable value found up to %g' % hi)
    while hi / lo > 1 + tolerance:
        mid = math.sqrt(lo * hi)
        if test(mid):
            hi = mid
        else:
            lo = mid
    return lo, hi, trials


# ------------------------------------------------------------------------------------------------
# one case, inside YADE
# ------------------------------------------------------------------------------------------------
def _saved_format():
    """The attribute names of the ViscBridge classes a saved bed holds: YADE's archives list every
    attribute in order, so a bed saved by a build with other attributes would not load again."""
    import yade.wrapper as yw
    classes = ('ViscBridgeTimeStepper', 'ViscBridgeGuard', 'Ip2_FrictMat_FrictMat_ViscBridgePhys',
               'Law2_ScGeom_ViscBridgePhys_HertzViscous', 'ViscBridgePhys', 'ViscBridgeImplicitSolver')
    return {c: sorted(getattr(yw, c)().dict()) for c in classes}


def _bed_path(case, cache_dir):
    # the format in the key: a bed cached by an older build is rebuilt, not loaded and refused
    identity = dict({k: case[k] for k in _BED_KEYS}, savedFormat=_saved_format())
    key = hashlib.sha1(json.dumps(identity, sort_keys=True).encode()).hexdigest()[:16]
    return os.path.join(cache_dir, 'bed-%s.yade.gz' % key)


def dry_bed(case, cache_dir):
    """Path of the case's bed settled dry (built and cached on first use)."""
    case = normalize_case(case)
    return settled_bed(_bed_path(case, cache_dir), **{k: case[k] for k in _BED_KEYS})


def settled_bed(path, **settling_args):
    """Save at `path` (unless it exists) a bed of :func:`viscbridge.scenes.settling` (with
    settling_args) settled dry, and return the path."""
    from yade import O
    from . import scenes
    if os.path.exists(path):
        return path
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    # dry, with strong contact damping (en = 0.2) so that the column comes to rest quickly
    scene = scenes.settling(viscosity=0.0, en=0.2, dt=None, trackEnergy=False, guard=False, **settling_args)
    # settle: the column falls in ~0.05 s; continue until the motion has died down
    scene.run(duration=0.08, stop_when_unstable=False)
    for _ in range(10):
        if scene.kinetic_energy() < 1e-4 * max(scene.released_energy(), 1e-30):
            break
        scene.run(duration=0.02, stop_when_unstable=False)
    tmp = path + '.part.yade.gz'
    O.save(tmp)
    os.replace(tmp, path)
    return path


def period_two_ringing(share=0.2):
    """Why the motion is a ringing at the time step's own frequency (physics.md §7), or None: more than
    `share` of the kinetic energy in bodies whose velocity reversed at each of the next two steps
    (+ − +).  Physics reverses a velocity only at a turning point; a mode at the stability limit
    (amplification −1) reverses it every step and stops decaying, so it outlasts a trial even where it
    stays bounded and the energy criterion does not fire.  Runs two steps more."""
    from yade import O, Vector3
    dynamic = [b for b in O.bodies if b.dynamic]
    history = [[Vector3(b.state.vel) for b in dynamic]]  # copies: the attribute is a live view
    for _ in range(2):
        O.run(1, True)
        history.append([Vector3(b.state.vel) for b in dynamic])
    ringing = total = 0.0
    for k, b in enumerate(dynamic):
        v0, v1, v2 = history[0][k], history[1][k], history[2][k]
        energy = 0.5 * b.state.mass * v2.squaredNorm()
        total += energy
        if v0.dot(v1) < 0 and v1.dot(v2) < 0:
            ringing += energy
    if total > 0 and ringing > share * total:
        return 'period-2 ringing (%.0f %% of the kinetic energy reverses every step)' % (100 * ringing / total)
    return None


class _Trial:
    """A wetted bed run at a fixed Δt; see the module docstring."""

    def __init__(self, case, bed):
        self.case, self.bed = case, bed

    def prepare(self):
        import random
        from yade import O, utils
        import yade.wrapper as yw
        from . import scenes
        O.load(self.bed)
        O.interactions.clear()  # every contact is re-created as a bridge with this liquid
        loop = next(e for e in O.engines if isinstance(e, yw.InteractionLoop))
        ip2 = loop.physDispatcher.functors[0]
        for k in _LIQUID_KEYS:
            setattr(ip2, k, self.case[k])
        loop.lawDispatcher.functors[0].integration = self.case['integration']
        engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeImplicitSolver)]
        if self.case['integration'] == 'implicit':  # the solver goes right before the integrator
            at = next(k for k, e in enumerate(engines) if isinstance(e, yw.NewtonIntegrator))
            engines.insert(at, yw.ViscBridgeImplicitSolver())
        O.engines = engines
        rng = random.Random(self.case['seed'] + 1)
        v = self.case['perturbation']
        for b in O.bodies:
            if b.dynamic:
                b.state.vel = tuple(rng.uniform(-v, v) for _ in range(3))
        self.z0 = {b.id: b.state.pos[2] for b in O.bodies if b.dynamic}
        self.ke0 = utils.kineticEnergy()
        self.capillary0 = scenes.capillary_input()

    def measures(self):
        """Kinetic energy, and the energy released since prepare(): potential energy and the
        capillary forces' input."""
        from yade import O, utils
        from . import scenes
        released = sum(O.bodies[i].state.mass * 9.81 * (z - O.bodies[i].state.pos[2]) for i, z in self.z0.items())
        return utils.kineticEnergy(), released + scenes.capillary_input() - self.capillary0

    def unstable_at(self, dt):
        """Run `steps` steps at dt; the instability criterion's reason, or None."""
        from yade import O
        import yade.wrapper as yw
        from .scenes import instability
        self.prepare()
        O.engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeTimeStepper)]
        O.dt = dt
        checks = 40
        for _ in range(checks):
            O.run(max(1, self.case['steps'] // checks), True)
            ke, released = self.measures()
            why = instability(ke, released, self.ke0)
            if why:
                return why
        return period_two_ringing() if self.case['verdict'] == 'period2' else None

    def stepper_dt(self):
        """The time stepper's Δt (default safety) on the wetted bed, with its bounds."""
        from yade import O
        import yade.wrapper as yw
        self.prepare()
        ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
        O.run(1, True)  # interactions are created and the stepper runs once
        for _ in range(60):  # dt may only grow by maxGrowth per step: let it settle
            O.run(1, True)
        contacts = [i for i in O.interactions if i.isReal]
        dyn = sum(1 for b in O.bodies if b.dynamic)
        return dict(dt_stepper=O.dt, dt_stepper_collision=ts.dtCollision, dt_stepper_viscous=ts.dtViscous,
                    governing=ts.governing, bridges=sum(1 for i in contacts if i.phys.bridge),
                    coordination=2.0 * len(contacts) / max(dyn, 1))


def find_critical_dt(case, cache_dir):
    """Bisection of the critical Δt of one case (runs inside YADE).  Returns a result dict."""
    from . import _registry, criteria
    case = normalize_case(case)
    started = time.time()
    trial = _Trial(case, dry_bed(case, cache_dir))
    info = trial.stepper_dt()
    r_small = case['radius'] * (1 - (case['sizeRatio'] - 1) / (case['sizeRatio'] + 1))
    s_min = case['sMinRel'] * r_small / 2
    t_v = criteria.viscous_decay_time(r_small, case['density'], case['viscosity'], s_min) if case['viscosity'] > 0 else math.inf
    rayleigh = criteria.rayleigh_dt(r_small, case['density'], case['young'], case['poisson'])
    guess = info['dt_stepper']
    lo, hi, trials = bisect_threshold(lambda dt: trial.unstable_at(dt), guess, 4 * guess, case['tolerance'])
    critical = math.sqrt(lo * hi)
    result = dict(case, key=case_key(case), dt_critical=critical, dt_stable=lo, dt_unstable=hi,
                  t_v=t_v, rayleigh_dt=rayleigh, trials=len(trials), wall_seconds=time.time() - started, **info)
    result['critical_over_tv'] = critical / t_v if math.isfinite(t_v) else None
    result['critical_over_stepper'] = critical / info['dt_stepper']
    return result


# ------------------------------------------------------------------------------------------------
# results, tables, parallel runs
# ------------------------------------------------------------------------------------------------
class ResultsFile:
    """JSON lines, one finished case per line, appended atomically (safe with parallel jobs)."""

    def __init__(self, path):
        self.path = path

    def append(self, result):
        import fcntl
        line = json.dumps(result, sort_keys=True) + '\n'
        os.makedirs(os.path.dirname(os.path.abspath(self.path)), exist_ok=True)
        with open(self.path, 'a') as fh:
            fcntl.flock(fh, fcntl.LOCK_EX)
            fh.write(line)
            fh.flush()
            os.fsync(fh.fileno())
            fcntl.flock(fh, fcntl.LOCK_UN)

    def read(self):
        if not os.path.exists(self.path):
            return []
        out = []
        with open(self.path) as fh:
            for line in fh:
                line = line.strip()
                if line:
                    try:
                        out.append(json.loads(line))
                    except json.JSONDecodeError:
                        pass  # a line cut by a kill: that case simply runs again
        return out

    def done_keys(self):
        return {r['key'] for r in self.read() if 'key' in r}


def _table_value(v):
    return repr(v) if isinstance(v, str) else ('%r' % v)


def write_table(cases, path, scan_dir):
    """A yade-batch table: one line per case (columns: every case field, plus scanDir).  Every case
    is checked before the file is touched, and the file is replaced whole."""
    fields = list(CASE_DEFAULTS)
    scan_dir = os.path.abspath(scan_dir)
    if re.search(r'\s', scan_dir):  # the table's columns are separated by white space
        raise ValueError('scan directory %r: a path with white space cannot go into a yade-batch table' % scan_dir)
    lines = [' '.join(['description'] + fields + ['scanDir'])]
    for c in unique_cases(cases):
        lines.append(' '.join([case_key(c)] + [_table_value(c[f]) for f in fields] + [repr(scan_dir)]))
    tmp = path + '.part'
    with open(tmp, 'w') as fh:
        fh.write('\n'.join(lines) + '\n')
    os.replace(tmp, path)
    return path


JOB_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'scan_job.py')


def run_cases(cases, scan_dir, jobs=2, progress=True):
    """Run every case not yet in scan_dir/results.jsonl, `jobs` at a time, through yade-batch.
    Returns the list of all results (old and new).

    scan_dir/cases.table gets the whole scan (what :func:`slurm_script` submits), scan_dir/todo.table
    the cases still to run (what yade-batch runs).  Raises CasesFailed when cases left no result or
    yade-batch reports them failed; KeyboardInterrupt (also on SIGTERM or SIGHUP) once yade-batch and
    its jobs are stopped."""
    if not (isinstance(jobs, int) and jobs >= 1):
        raise ValueError('run_cases: jobs=%r is out of range; allowed: integer >= 1' % (jobs,))
    cases = unique_cases(cases)
    scan_dir = os.path.abspath(scan_dir)
    os.makedirs(scan_dir, exist_ok=True)
    write_table(cases, os.path.join(scan_dir, 'cases.table'), scan_dir)
    results = ResultsFile(os.path.join(scan_dir, 'results.jsonl'))
    done = results.done_keys()
    todo = [c for c in cases if case_key(c) not in done]
    if progress:
        print('scan: %d cases, %d already done, %d to run' % (len(cases), len(cases) - len(todo), len(todo)), file=sys.stderr)
    if todo:
        reported = _run_batch(write_table(todo, os.path.join(scan_dir, 'todo.table'), scan_dir), scan_dir, jobs,
                              _progress(len(todo)) if progress else None, lambda: len(results.done_keys() - done))
        failed = _failures(todo, results.done_keys(), reported, scan_dir)
        if failed:
            raise CasesFailed(failed, scan_dir)
    return results.read()


def _run_batch(table, scan_dir, jobs, bar, finished):
    """Run yade-batch on `table`; returns the descriptions (case keys) of the jobs it reports failed."""
    # per-case logs beside the results (yade-batch's default puts them beside the job script,
    # inside the installed package); relative, since yade-batch runs in scan_dir
    cmd = ['yade-batch', '--job-threads=1', '-j', str(jobs), '--log', 'case-@.log', table, JOB_SCRIPT]
    log_path = os.path.join(scan_dir, 'yade-batch.log')
    with open(log_path, 'ab') as log:
        start = log.tell()  # the log is appended to by every run: this run's part starts here
        # its own session: Ctrl-C in a terminal reaches this process only, which stops the whole
        # group (yade-batch and its jobs) and then reports
        proc = subprocess.Popen(cmd, cwd=scan_dir, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            with _signals(_interrupt):
                while proc.poll() is None:
                    time.sleep(2)
                    if bar:
                        bar(finished())
        finally:
            if proc.returncode is None:
                with _signals(signal.SIG_IGN):  # a second Ctrl-C must not leave the jobs running
                    _stop_group(proc)
            if bar:
                bar(finished(), final=True)
    with open(log_path, 'rb') as fh:
        fh.seek(start)
        output = fh.read().decode(errors='replace')
    return set(re.findall(r'^#\d+ \((\w+)\) FAILED', output, re.M))


def _interrupt(signum, frame):
    raise KeyboardInterrupt(signal.Signals(signum).name)


@contextlib.contextmanager
def _signals(handler):
    """Within: SIGINT, SIGTERM and SIGHUP go to `handler` unless ignored (only the main thread can
    set handlers)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
    for s, h in old.items():
        if h is not signal.SIG_IGN:  # an ignored signal stays ignored (nohup, a background job)
            signal.signal(s, handler)
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, signal.SIG_DFL if h is None else h)


def _stop_group(proc, grace=5.0):
    """Stop yade-batch and the jobs it started (its process group): SIGTERM, then SIGKILL for
    whatever outlives `grace` seconds."""
    os.killpg(proc.pid, signal.SIGTERM)
    deadline = time.monotonic() + grace
    # wait without reaping: while yade-batch is not reaped its group id cannot be taken by another
    while time.monotonic() < deadline and os.waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOHANG | os.WNOWAIT) is None:
        time.sleep(0.1)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()


def _failures(todo, done, reported, scan_dir):
    """(case, error) for each case of `todo` without a result or reported failed by yade-batch."""
    failed = []
    for c in todo:
        key = case_key(c)
        if key not in done or key in reported:
            error = _log_error(os.path.join(scan_dir, 'case-%s.log' % key))
            failed.append((c, error if key not in done else 'wrote its result, then failed: ' + error))
    return failed


def _log_error(path):
    """The error a case log ends with (its last exception line, else its last line)."""
    if not os.path.exists(path):
        return 'not started (no %s; see yade-batch.log)' % os.path.basename(path)
    with open(path, errors='replace') as fh:
        lines = [line.strip() for line in fh if line.strip()]
    errors = [line for line in lines if re.match(r'[\w.]*(Error|Exception|Interrupt)\b', line)]
    return (errors or lines or ['no result and an empty log'])[-1]


def _progress(total):
    try:
        from tqdm import tqdm
        bar = tqdm(total=total, unit='case', file=sys.stderr)

        def update(n, final=False):
            bar.update(n - bar.n)
            if final:
                bar.close()
        return update
    except ImportError:
        def update(n, final=False):
            print('scan: %d/%d cases done' % (n, total), file=sys.stderr)
        return update


def _scan_dir(scan_dir):
    if not os.path.isdir(scan_dir):
        raise ScanError('no such scan directory: %s' % scan_dir)
    return scan_dir


def collect(scan_dir):
    """Write scan_dir/results.csv from results.jsonl (latest result per case) and return the rows."""
    import csv
    rows = {}
    for r in ResultsFile(os.path.join(_scan_dir(scan_dir), 'results.jsonl')).read():
        rows[r.get('key')] = r
    rows = list(rows.values())
    if rows:
        keys = sorted({k for r in rows for k in r})
        with open(os.path.join(scan_dir, 'results.csv'), 'w', newline='') as fh:
            w = csv.DictWriter(fh, fieldnames=keys)
            w.writeheader()
            w.writerows(rows)
    return rows


SLURM_TEMPLATE = """#!/bin/bash
# Slurm array job for the ViscBridge scan table {table} ({n} cases).
# Every task runs one table line with the same job script yade-batch uses; results are appended to
# {scan_dir}/results.jsonl.  A task whose case is already there ends at once, so the whole array
# can simply be resubmitted after failed or cancelled tasks.
#SBATCH --job-name=viscbridge-scan
#SBATCH --array=2-{last}
#SBATCH --cpus-per-task=1
#SBATCH --time=02:00:00
#SBATCH --output={scan_dir}/slurm-%A_%a.log
export OMP_NUM_THREADS=1
# line N of the table (line 1 is the header) is the case of task N
export YADE_BATCH={table}:$SLURM_ARRAY_TASK_ID
# on the cluster, use its YADE 2025.2 with the plugin installed (cmake --install build), or:
#   {repo}/yadew run {job}
yade -n -x {job}
"""


def slurm_script(scan_dir):
    """Write scan_dir/scan.sbatch, an array job over scan_dir/cases.table (the whole scan)."""
    table = os.path.abspath(os.path.join(_scan_dir(scan_dir), 'cases.table'))
    if not os.path.exists(table):
        raise ScanError('no %s; write it with the "table" or "run" command' % table)
    with open(table) as fh:
        n = sum(1 for line in fh if line.strip()) - 1
    path = os.path.join(scan_dir, 'scan.sbatch')
    repo = os.path.dirname(os.path.dirname(os.path.dirname(JOB_SCRIPT)))
    with open(path, 'w') as fh:
        fh.write(SLURM_TEMPLATE.format(table=table, n=n, last=n + 1, scan_dir=os.path.abspath(scan_dir), job=JOB_SCRIPT, repo=repo))
    return path


# ------------------------------------------------------------------------------------------------
# command line
# ------------------------------------------------------------------------------------------------
def _parse_value(text):
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def _parse_assignments(items, lists):
    out = {}
    for item in items or []:
        if '=' not in item:
            raise ValueError('expected FIELD=VALUE%s, got %r' % (',VALUE...' if lists else '', item))
        k, v = item.split('=', 1)
        out[k] = [_parse_value(x) for x in v.split(',')] if lists else _parse_value(v)
    return out


def _cases_from_args(args):
    base = _parse_assignments(args.base, lists=False)
    variations = _parse_assignments(args.vary, lists=True)
    if args.grid:
        return grid(base, **variations)
    return one_at_a_time(base, **variations)


def fields_help():
    """The list of case fields of --help: name, default, unit, meaning and allowed values."""
    lines = ['case fields (FIELD=VALUE; the unit is SI, "-" for none):',
             '  %-16s %-14s %-6s %s' % ('FIELD', 'DEFAULT', 'UNIT', 'MEANING; ALLOWED')]
    for name, default in CASE_DEFAULTS.items():
        shown = '%g' % default if isinstance(default, float) else str(default)
        field = CASE_FIELDS[name]
        lines.append('  %-16s %-14s %-6s %s; %s' % (name, shown, field.unit or '-', field.meaning, _allowed(name)))
    return '\n'.join(lines)


_COMMANDS = dict(
    run="run the scan's cases not yet in DIR/results.jsonl through yade-batch",
    table='only write DIR/cases.table, the yade-batch table of the scan',
    collect='write DIR/results.csv from DIR/results.jsonl (the latest result per case)',
    slurm='write DIR/scan.sbatch, a Slurm array job over the whole scan (DIR/cases.table); '
          'its tasks skip finished cases, so it can be resubmitted as it is',
)


def build_parser():
    """The command line's parser; every command and option has a help text, and the help of the
    parser and of `run` and `table` lists the case fields."""
    fmt = dict(formatter_class=argparse.RawDescriptionHelpFormatter, epilog=fields_help())
    p = argparse.ArgumentParser(prog='python3 -m viscbridge.scan', description=__doc__.split('\n\n')[0], **fmt)
    sub = p.add_subparsers(dest='command', required=True, metavar='COMMAND')
    for name, text in _COMMANDS.items():
        s = sub.add_parser(name, help=text, description=text, **(fmt if name in ('run', 'table') else {}))
        s.add_argument('dir', metavar='DIR', help='scan directory' + (' (created if missing)' if name in ('run', 'table') else ''))
        if name in ('run', 'table'):
            _add_case_options(s)
        if name == 'run':
            s.add_argument('-j', '--jobs', type=int, default=os.cpu_count() or 1,
                           help='cases run at the same time (default: the number of CPUs, %(default)s)')
    return p


def _add_case_options(parser):
    parser.add_argument('--base', nargs='*', action='extend', metavar='FIELD=VALUE',
                        help='fields of the base case (the others at their defaults)')
    parser.add_argument('--vary', nargs='*', action='extend', metavar='FIELD=V1,V2',
                        help='values of a field, varied one field at a time from the base case (all combinations with --grid)')
    parser.add_argument('--grid', action='store_true', help='run every combination of the --vary values')


def _run(args):
    cases = _cases_from_args(args)  # every case is checked before anything is written
    try:
        rows = run_cases(cases, args.dir, jobs=args.jobs)
    finally:
        if os.path.isdir(args.dir):  # what finished is in results.csv too, whatever happened after
            collect(args.dir)
    print('scan: %d results in %s' % (len(rows), os.path.join(os.path.abspath(args.dir), 'results.csv')))


def _table(args):
    cases = _cases_from_args(args)
    os.makedirs(args.dir, exist_ok=True)
    print(write_table(cases, os.path.join(args.dir, 'cases.table'), args.dir))


def _collect(args):
    rows = collect(args.dir)
    if not rows:
        raise ScanError('no finished case in %s' % os.path.join(args.dir, 'results.jsonl'))
    print('%d results -> %s' % (len(rows), os.path.join(args.dir, 'results.csv')))


def _slurm(args):
    print(slurm_script(args.dir))


def main(argv=None):
    """The command line; returns the exit status.  Errors are reported on stderr without a traceback."""
    args = build_parser().parse_args(argv)
    try:
        dict(run=_run, table=_table, collect=_collect, slurm=_slurm)[args.command](args)
    except KeyboardInterrupt:
        resume = ('; yade-batch stopped, finished cases kept in %s; run the same command again to resume'
                  % os.path.join(os.path.abspath(args.dir), 'results.jsonl')) if args.command == 'run' else ''
        print('scan: interrupted%s' % resume, file=sys.stderr)
        return 130
    except (ValueError, ScanError, OSError) as e:
        print('scan: error: %s' % e, file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
