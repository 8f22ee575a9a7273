# The implicit step against the explicit one on the product's drum, on the same landed bed: what a
# drum step costs with each scheme, where the time goes, and how many hours a revolution takes.
#
#   ./yadew run bench/drum_scaling.py [MODEL:N[@MU] ...] [--rounds R] [--threads T]
#        (default: film:1000 film:1000@100 fixed:1000 fixed:1000@100 fixed:3000 film:10000)
#
# MODEL is the liquid (film: 15 % of the spheres wetted; fixed: every contact a bridge), N the
# spheres, MU the viscosity [Pa·s] (default 1).  Beds are landed once by bench/drum_cost.py's rule
# and kept in bench/.cache/drum/ (a bed at another viscosity is landed at that viscosity).
#
# docs/perf/drum_scaling.csv keeps one row per configuration and thread count: a run replaces the
# rows of what it measured and keeps the others.
#
# Every round runs each configuration in its own `yade -n -j T` process, which loads the landed bed
# and measures three phases one after the other on the state it reached:
#   implicit   the scene as scenes.drum makes it (implicit viscous forces, the time stepper): WARM
#              steps (the first factorisation after the load), then a window of about 10⁶
#              sphere-steps (drum_cost.window_steps) with YADE's engine timers;
#   explicit   the law's integration switched to 'explicit' on the same state and the implicit
#              solver taken out of O.engines, as a user runs the explicit scheme: the time stepper
#              moves Δt to the explicit limit of the live network (its P14 bound) within WARM steps,
#              then the same window;
#   yade dry   the same spheres and drum with YADE's own dry Hertz–Mindlin (Ip2_FrictMat_FrictMat_
#              MindlinPhys, Law2_ScGeom_MindlinPhys_Mindlin, the interactions made anew) at the explicit
#              phase's Δt: the cost of a YADE drum step without liquid.
# The fastest of the rounds is kept per configuration and phase (common.interleaved explains why);
# the slowest is written beside it.  Hours per revolution: the drum's period over the phase's Δt,
# times its engine seconds per step.  The implicit solver's phases per step (timeGather_per_step …
# timeEstimate_per_step: the gather, the factor's refresh, the solve, … the time stepper's error
# estimate) are its own timers over the window.  Engine shares: the time stepper's and the guard's time over
# the step's.  Peak RSS: the measuring process's maximum resident set (getrusage).
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
sys.path.insert(0, HERE)
import common  # noqa: E402
import drum_cost  # noqa: E402

DEFAULT = ['film:1000', 'film:1000@100', 'fixed:1000', 'fixed:1000@100', 'fixed:3000', 'film:10000']
ROUNDS, WARM = 3, 20


def parse(config):
    """'fixed:1000@100' -> ('fixed', 1000, 100.0)."""
    model, _, rest = config.partition(':')
    n, _, mu = rest.partition('@')
    if model not in drum_cost.MODELS or not n.isdigit():
        raise SystemExit('drum_scaling: configuration %r is not MODEL:N[@MU] with MODEL one of %s' % (config, ', '.join(drum_cost.MODELS)))
    return model, int(n), float(mu) if mu else 1.0


def timed_window(steps):
    """Engine seconds per step over `steps` steps, and each engine type's share of them."""
    from yade import O
    O.timingEnabled = True
    for e in O.engines:
        e.execTime, e.execCount = 0, 0
    t0 = O.time
    O.run(steps, True)
    O.timingEnabled = False
    total = sum(e.execTime for e in O.engines)
    shares = {}
    for e in O.engines:
        shares[type(e).__name__] = shares.get(type(e).__name__, 0.0) + e.execTime / total
    return total * 1e-9 / steps, (O.time - t0) / steps, shares


def solver_counts(before):
    """CG iterations, refactorisations and the solver's phases (common.SOLVER_TIMES, as seconds) per
    solve since `before` (the solver's counters then)."""
    from yade import O
    import yade.wrapper as yw
    s = next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver))
    now = dict(solves=s.solves, totalIterations=s.totalIterations, factorisations=s.factorisations,
               **{k: getattr(s, k) for k in common.SOLVER_TIMES})
    if before is None:
        return now
    solves = max(1, now['solves'] - before['solves'])
    return dict(cg_iterations_per_step=(now['totalIterations'] - before['totalIterations']) / solves,
                factorisations_per_step=(now['factorisations'] - before['factorisations']) / solves,
                **{k + '_per_step': (now[k] - before[k]) / solves for k in common.SOLVER_TIMES})


def phase_row(phase, seconds, dt, shares):
    return {phase + '_seconds_per_step': seconds, phase + '_dt': dt,
            phase + '_stepper_share': shares.get('ViscBridgeTimeStepper', 0.0),
            phase + '_guard_share': shares.get('ViscBridgeGuard', 0.0)}


def yade_dry_engines():
    """YADE's own dry drum: the facets' rotation engine kept, the liquid's engines left out."""
    from yade import O
    import yade.wrapper as yw
    rotation = [e for e in O.engines if isinstance(e, yw.RotationEngine)]
    newton = next(e for e in O.engines if isinstance(e, yw.NewtonIntegrator))
    return [yw.ForceResetter(),
            yw.InsertionSortCollider([yw.Bo1_Sphere_Aabb(), yw.Bo1_Facet_Aabb()]),
            yw.InteractionLoop([yw.Ig2_Sphere_Sphere_ScGeom(), yw.Ig2_Facet_Sphere_ScGeom()],
                               [yw.Ip2_FrictMat_FrictMat_MindlinPhys()],
                               [yw.Law2_ScGeom_MindlinPhys_Mindlin()])] + rotation + [
            yw.NewtonIntegrator(gravity=newton.gravity, damping=0.0)]


def measure(model, n, mu, out):
    """One round of one configuration: implicit, explicit and YADE's dry drum on the landed bed."""
    from yade import O
    import yade.wrapper as yw
    import viscbridge.measures as measures
    O.load(drum_cost.scene_path(model, n, mu))
    spheres = sum(1 for b in O.bodies if isinstance(b.shape, yw.Sphere))
    steps = drum_cost.window_steps(n)
    row = dict(liquidModel=model, spheres=spheres, viscosity=mu, window_steps=steps, threads=O.numThreads)
    O.run(WARM, True)
    before = solver_counts(None)
    seconds, dt, shares = timed_window(steps)
    row.update(phase_row('implicit', seconds, dt, shares), bridges=measures.bridge_count(),
               solver_share=shares.get('ViscBridgeImplicitSolver', 0.0), **solver_counts(before))
    law = next(f for e in O.engines if isinstance(e, yw.InteractionLoop) for f in e.lawDispatcher.functors)
    law.integration = 'explicit'  # the scene explicit as a user would run it: without the implicit solver
    O.engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeImplicitSolver)]
    O.run(WARM, True)
    seconds, dt, shares = timed_window(steps)
    row.update(phase_row('explicit', seconds, dt, shares))
    O.interactions.clear()
    O.engines = yade_dry_engines()
    O.run(WARM, True)
    seconds, _, _ = timed_window(steps)
    row.update(yade_dry_seconds_per_step=seconds, peak_rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
    json.dump(row, open(out, 'w'))


def configuration_key(row):
    """What a row measured: the configuration and the threads (the CSV keeps each one's last run)."""
    return row['liquidModel'], int(float(row['spheres'])), float(row['viscosity']), int(float(row['threads']))


def worker(args, threads):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, 'r.json')
        done = subprocess.run(['yade', '-n', '-j%d' % threads, '-x', os.path.join(HERE, 'drum_scaling.py')] + args + [out],
                              capture_output=True, text=True)
        if done.returncode != 0 or not os.path.exists(out):
            raise RuntimeError('drum_scaling %s failed:\n%s' % (' '.join(args), done.stdout[-3000:] + done.stderr[-3000:]))
        return json.load(open(out))


def summary(configs, samples):
    """Per configuration: the fastest round of each phase, the slowest beside it, and the ratios."""
    rows = []
    for c in configs:
        runs = samples[c]
        row = dict(min(runs, key=lambda r: r['implicit_seconds_per_step']))
        for phase in ('implicit', 'explicit', 'yade_dry'):
            key = phase + '_seconds_per_step'
            fastest = min(runs, key=lambda r: r[key])
            row[key], row[phase + '_seconds_per_step_slowest'] = fastest[key], max(r[key] for r in runs)
        for phase in ('implicit', 'explicit', 'yade_dry'):
            row[phase + '_microseconds_per_sphere_step'] = 1e6 * row[phase + '_seconds_per_step'] / row['spheres']
        row['implicit_over_explicit_step'] = row['implicit_seconds_per_step'] / row['explicit_seconds_per_step']
        row['explicit_over_yade_dry_step'] = row['explicit_seconds_per_step'] / row['yade_dry_seconds_per_step']
        period = drum_cost.period(c[1])
        for phase in ('implicit', 'explicit'):
            row[phase + '_hours_per_revolution'] = period / row[phase + '_dt'] * row[phase + '_seconds_per_step'] / 3600
        row['time_to_solution_gain'] = row['explicit_hours_per_revolution'] / row['implicit_hours_per_revolution']
        row['rounds'] = len(runs)
        rows.append(row)
    return rows


def main(configs, rounds, threads):
    began = time.perf_counter()
    for model, n, mu in configs:
        drum_cost.ensure_landed(model, n, mu)
    samples = {c: [] for c in configs}
    for r in range(rounds):
        for c in configs:
            s = worker(['--measure', c[0], str(c[1]), repr(c[2])], threads)
            samples[c].append(s)
            print('round %d %-5s %6d spheres μ=%g: implicit %.4f s/step (dt %.3g), explicit %.4f s/step (dt %.3g), YADE dry %.4f s/step'
                  % (r + 1, c[0], c[1], c[2], s['implicit_seconds_per_step'], s['implicit_dt'], s['explicit_seconds_per_step'],
                     s['explicit_dt'], s['yade_dry_seconds_per_step']), flush=True)
    rows = summary(configs, samples)
    print('\nthe drum, %d thread(s), fastest of %d interleaved rounds:' % (threads, rounds))
    print('%-5s %7s %6s %10s %10s %8s %8s %9s %9s %8s %8s' % ('model', 'spheres', 'μ', 'impl s/st', 'expl s/st', 'ratio', 'CG/st',
                                                             'impl h/rev', 'expl h/rev', 'stepper', 'guard'))
    for r in rows:
        print('%-5s %7d %6g %10.4f %10.4f %8.2f %8.2f %9.2f %9.1f %7.1f%% %7.1f%%' % (
            r['liquidModel'], r['spheres'], r['viscosity'], r['implicit_seconds_per_step'], r['explicit_seconds_per_step'],
            r['implicit_over_explicit_step'], r['cg_iterations_per_step'], r['implicit_hours_per_revolution'],
            r['explicit_hours_per_revolution'], 100 * r['implicit_stepper_share'], 100 * r['implicit_guard_share']))
    out = os.path.join(common.RESULTS, 'drum_scaling.csv')
    print('written', common.write_rows(out, common.rows_with_earlier(out, rows, configuration_key)))
    print('bench took %.1f min' % ((time.perf_counter() - began) / 60))


if os.path.basename(sys.argv[0]) != 'drum_scaling.py':
    pass  # imported (tests, another bench): nothing to run
elif len(sys.argv) > 1 and sys.argv[1] == '--measure':
    measure(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5])
else:
    args, configs, rounds, threads = sys.argv[1:], [], ROUNDS, 1
    while args:
        a = args.pop(0)
        if a == '--rounds':
            rounds = int(args.pop(0))
        elif a == '--threads':
            threads = int(args.pop(0))
        else:
            configs.append(parse(a))
    main(configs or [parse(c) for c in DEFAULT], rounds, threads)
