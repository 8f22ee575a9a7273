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

Every finished case is appended to ``DIR/results.jsonl`` at once; re-running skips finished cases,
so a killed scan resumes where it stopped.
"""
import argparse
import hashlib
import itertools
import json
import math
import os
import subprocess
import sys
import time

__all__ = ['CASE_DEFAULTS', 'normalize_case', 'case_key', 'one_at_a_time', 'grid', 'bisect_threshold',
           'find_critical_dt', 'ResultsFile', 'write_table', 'run_cases', 'collect']

#: Every field a case can set, with its default.  Liquid/model fields go to
#: Ip2_FrictMat_FrictMat_ViscBridgePhys; the rest describe the bed and the trial.
CASE_DEFAULTS = dict(
    n=300, radius=0.5e-3, sizeRatio=1.0, density=2500.0, young=1e7, poisson=0.3, friction=0.5, seed=5,
    viscosity=1.0, sMinRel=1e-3, bridgeVolumeRel=0.01, contactAngle=0.0,
    normalModel='adamsPerchard', tangentialModel='slip', en=1.0, integration='explicit',
    steps=2000, perturbation=0.01, tolerance=0.02,
)
_LIQUID_KEYS = ('viscosity', 'sMinRel', 'bridgeVolumeRel', 'contactAngle', 'normalModel', 'tangentialModel', 'en')
_BED_KEYS = ('n', 'radius', 'sizeRatio', 'density', 'young', 'poisson', 'friction', 'seed')


def normalize_case(case):
    """The case with defaults filled in; ValueError on unknown fields."""
    unknown = set(case) - set(CASE_DEFAULTS)
    if unknown:
        raise ValueError('scan case: unknown field(s) %s; allowed: %s' % (', '.join(sorted(unknown)), ', '.join(CASE_DEFAULTS)))
    out = dict(CASE_DEFAULTS)
    out.update(case)
    for k in ('n', 'steps', 'seed'):
        if int(out[k]) != out[k]:
            raise ValueError('scan case: %s=%r is out of range; allowed: an integer' % (k, out[k]))
        out[k] = int(out[k])
    checks = (('n', 1, None), ('steps', 1, None), ('radius', 0, None), ('density', 0, None), ('young', 0, None),
              ('tolerance', 0, None), ('perturbation', None, None), ('viscosity', None, None))
    for k, above, _ in checks:
        v = out[k]
        if not isinstance(v, (int, float)) or not math.isfinite(v) or (above is not None and not v > above) or v < 0:
            raise ValueError('scan case: %s=%r is out of range; allowed: %s' % (k, v, '> %g' % above if above is not None else '>= 0'))
    if not 1 <= out['sizeRatio'] <= 5:
        raise ValueError('scan case: sizeRatio=%r is out of range; allowed: [1, 5]' % (out['sizeRatio'],))
    if out['integration'] not in ('explicit', 'implicit'):
        raise ValueError("scan case: integration=%r is out of range; allowed: 'explicit', 'implicit'" % (out['integration'],))
    return out


def case_key(case):
    """A stable identifier of a (normalized) case: what resuming compares."""
    text = json.dumps(normalize_case(case), sort_keys=True)
    return hashlib.sha1(text.encode()).hexdigest()[:16]


def one_at_a_time(base, **variations):
    """The base case, then each listed value of each field with the others at the base values."""
    base = normalize_case(base)
    cases, seen = [base], {case_key(base)}
    for field, values in variations.items():
        for v in values:
            c = dict(base, **{field: v})
            if case_key(c) not in seen:
                seen.add(case_key(c))
                cases.append(normalize_case(c))
    return cases


def grid(base=None, **axes):
    """The cartesian product of the listed values (other fields from `base`)."""
    base = normalize_case(base or {})
    names = list(axes)
    return [normalize_case(dict(base, **dict(zip(names, values)))) for values in itertools.product(*(axes[n] for n in names))]


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
def _bed_path(case, cache_dir):
    key = hashlib.sha1(json.dumps({k: case[k] for k in _BED_KEYS}, sort_keys=True).encode()).hexdigest()[:16]
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


class _Trial:
    """A wetted bed run at a fixed Δt; see the module docstring."""

    def __init__(self, case, bed):
        self.case, self.bed = case, bed

    def prepare(self):
        import random
        from yade import O, utils
        import yade.wrapper as yw
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

    def measures(self):
        from yade import O, utils
        released = sum(O.bodies[i].state.mass * 9.81 * (z - O.bodies[i].state.pos[2]) for i, z in self.z0.items())
        return utils.kineticEnergy(), released

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
        return None

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
    from . import criteria
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
    """A yade-batch table: one line per case (columns: every case field, plus scanDir)."""
    fields = list(CASE_DEFAULTS)
    with open(path, 'w') as fh:
        fh.write(' '.join(['description'] + fields + ['scanDir']) + '\n')
        for c in cases:
            c = normalize_case(c)
            fh.write(' '.join([case_key(c)] + [_table_value(c[f]) for f in fields] + [repr(os.path.abspath(scan_dir))]) + '\n')
    return path


JOB_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'scan_job.py')


def run_cases(cases, scan_dir, jobs=2, progress=True):
    """Run every case not yet in scan_dir/results.jsonl, `jobs` at a time, through yade-batch.
    Returns the list of all results (old and new)."""
    if not (isinstance(jobs, int) and jobs >= 1):
        raise ValueError('run_cases: jobs=%r is out of range; allowed: integer >= 1' % (jobs,))
    scan_dir = os.path.abspath(scan_dir)
    os.makedirs(scan_dir, exist_ok=True)
    results = ResultsFile(os.path.join(scan_dir, 'results.jsonl'))
    done = results.done_keys()
    todo = [normalize_case(c) for c in cases if case_key(c) not in done]
    if progress:
        print('scan: %d cases, %d already done, %d to run' % (len(cases), len(cases) - len(todo), len(todo)), file=sys.stderr)
    if todo:
        table = write_table(todo, os.path.join(scan_dir, 'cases.table'), scan_dir)
        # per-case logs beside the results (yade-batch's default puts them beside the job script,
        # inside the installed package); relative, since yade-batch runs in scan_dir
        cmd = ['yade-batch', '--job-threads=1', '-j', str(jobs), '--log', 'case-@.log', table, JOB_SCRIPT]
        with open(os.path.join(scan_dir, 'yade-batch.log'), 'a') as log:
            proc = subprocess.Popen(cmd, cwd=scan_dir, stdout=log, stderr=subprocess.STDOUT)
            bar = _progress(len(todo)) if progress else None
            while proc.poll() is None:
                time.sleep(2)
                if bar:
                    bar(len(results.done_keys() - done))
            if bar:
                bar(len(results.done_keys() - done), final=True)
        if proc.returncode != 0:
            raise RuntimeError('yade-batch failed (exit %d); see %s' % (proc.returncode, os.path.join(scan_dir, 'yade-batch.log')))
    return results.read()


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


def collect(scan_dir):
    """Write scan_dir/results.csv from results.jsonl (latest result per case) and return the rows."""
    import csv
    rows = {}
    for r in ResultsFile(os.path.join(scan_dir, 'results.jsonl')).read():
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
# {scan_dir}/results.jsonl, so failed or cancelled tasks can simply be resubmitted.
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
    table = os.path.abspath(os.path.join(scan_dir, 'cases.table'))
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
            raise SystemExit('scan: expected FIELD=VALUE%s, got %r' % (',VALUE...' if lists else '', item))
        k, v = item.split('=', 1)
        out[k] = [_parse_value(x) for x in v.split(',')] if lists else _parse_value(v)
    return out


def _cases_from_args(args):
    base = _parse_assignments(args.base, lists=False)
    variations = _parse_assignments(args.vary, lists=True)
    if args.grid:
        return grid(base, **variations)
    return one_at_a_time(base, **variations)


def main(argv=None):
    p = argparse.ArgumentParser(prog='python3 -m viscbridge.scan', description=__doc__.split('\n\n')[0])
    sub = p.add_subparsers(dest='command', required=True)
    for name in ('run', 'table'):
        s = sub.add_parser(name)
        s.add_argument('dir')
        s.add_argument('--base', nargs='*', help='FIELD=VALUE of the base case')
        s.add_argument('--vary', nargs='*', help='FIELD=V1,V2,... (one at a time, or all combinations with --grid)')
        s.add_argument('--grid', action='store_true')
        if name == 'run':
            s.add_argument('-j', '--jobs', type=int, default=os.cpu_count() or 1)
    sub.add_parser('collect').add_argument('dir')
    sub.add_parser('slurm').add_argument('dir')
    args = p.parse_args(argv)
    if args.command == 'run':
        rows = run_cases(_cases_from_args(args), args.dir, jobs=args.jobs)
        collect(args.dir)
        print('scan: %d results in %s' % (len(rows), os.path.join(os.path.abspath(args.dir), 'results.csv')))
    elif args.command == 'table':
        os.makedirs(args.dir, exist_ok=True)
        print(write_table(_cases_from_args(args), os.path.join(args.dir, 'cases.table'), args.dir))
    elif args.command == 'collect':
        rows = collect(args.dir)
        print('%d results -> %s' % (len(rows), os.path.join(args.dir, 'results.csv')))
    elif args.command == 'slurm':
        print(slurm_script(args.dir))


if __name__ == '__main__':
    main()
