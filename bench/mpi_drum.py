# The product's drum under yade.mpy: wall time per step serially and on 2 and 3 MPI ranks (mpy's
# master plus one or two workers), hours per revolution, mpy's own overhead per step, and a model of
# strong and weak scaling fitted to them (docs/cluster.md, "The drum over ranks").
#
#   ./yadew run bench/mpi_drum.py [[MODEL:]SPHERES ...]   (default fixed:1000 fixed:3000; MODEL fixed or film)
#   ./yadew run bench/mpi_drum.py --model                 (the model of the last measurement)
#
# The drum of bench/drum_cost.py with every contact wet (liquidModel='fixed') or with film liquid
# (its default: 15 % of the spheres wet): spheres of 1 mm, fill 0.35, Fr = 0.05, μ = 1 Pa·s,
# implicit, the full engine list.  Its bed lands once serially (drum_cost.land, cached in bench/.cache/drum/); each run loads
# it, splits it into slabs along x (viscbridge.mpi.decompose()), takes WARMUP steps (mpy's split and
# the solver's first factorisation) and times STEPS.  One thread per rank.  This VM has 2 cores:
# 3 ranks oversubscribe them, and mpy's master (no spheres) polls while it waits, so the 3-rank
# times are pessimistic.  The fastest of ROUNDS interleaved rounds, the slowest kept beside it.
# Writes docs/perf/mpi_drum.csv (rows of other configurations measured before are kept); a
# scaling model is fitted to the rows of each liquid model measured at two sizes or more.
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
sys.path.insert(0, HERE)
import common  # noqa: E402
import drum_cost  # noqa: E402  (its landed beds)

OUT = os.path.join(common.RESULTS, 'mpi_drum.csv')
WARMUP, STEPS, ROUNDS = 10, 20, 2


def worker(model, n, out):
    import math
    from yade import O
    import yade.wrapper as yw
    import viscbridge.mpi
    distributed = 'OMPI_COMM_WORLD_SIZE' in os.environ
    O.load(drum_cost.scene_path(model, n))
    period = 2 * math.pi / abs(next(e for e in O.engines if isinstance(e, yw.RotationEngine)).angularVelocity)
    viscbridge.mpi.decompose(axis=0)
    if distributed:
        from yade import mpy as mp
        run = lambda k: mp.mpirun(k, mp.numThreads)  # noqa: E731
    else:
        run = lambda k: O.run(k, True)  # noqa: E731
    run(WARMUP)
    solver = next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver))
    iterations0 = solver.totalIterations
    t0 = time.perf_counter()
    run(STEPS)
    seconds = (time.perf_counter() - t0) / STEPS
    iterations = viscbridge.mpi.allgather(solver.totalIterations - iterations0)
    if viscbridge.mpi.rank() == 0:
        json.dump(dict(model=model, spheres=n, ranks=viscbridge.mpi.ranks(), steps=STEPS, seconds_per_step=seconds, dt=O.dt,
                       hours_per_revolution=seconds * period / O.dt / 3600,
                       cg_iterations_per_step=max(iterations) / STEPS), open(out, 'w'))


def land(model, n):
    if not os.path.exists(drum_cost.scene_path(model, n)):
        with tempfile.TemporaryDirectory() as tmp:
            subprocess.run(['yade', '-n', '-j1', '-x', os.path.join(HERE, 'drum_cost.py'), '--land', model, str(n),
                            os.path.join(tmp, 'landed.json')], check=True, env=dict(os.environ, OMP_NUM_THREADS='1'),
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def measure(model, n, ranks):
    return common.run_on_ranks(os.path.join(HERE, 'mpi_drum.py'), ['--worker', model, n], ranks)


def configuration(arg):
    """'film:10000' -> ('film', 10000); a bare size is the fixed liquid's."""
    model, _, n = arg.rpartition(':')
    return model or 'fixed', int(n)


def configuration_key(row):
    """What a row measured (a row of an older CSV without the model column: the fixed liquid)."""
    return row.get('model') or 'fixed', int(float(row['spheres'])), int(float(row['ranks']))


def numeric(row):
    """A row with its numbers as numbers (those read back from the CSV are text)."""
    return {k: float(v) if k != 'model' and isinstance(v, str) and v else v for k, v in row.items()}


def model(rows, liquid='fixed'):
    """A worker's step t_w(n) = c·n^p for n spheres (fitted to the one-worker runs of the two largest
    sizes: the factor's fill makes it grow faster than n), times k, what splitting costs on top (the
    two-worker run of the largest size against t_w of half its spheres: the block-Jacobi
    preconditioner's extra CG iterations, the halo exchanges, and here the oversubscribed cores).
    Strong and weak scaling then follow t(N, W) = k·c·(N/W)^p.  Fitted to the fastest rounds; an
    extrapolation, not a measurement beyond them."""
    import math
    rows = [r for r in rows if r.get('model', 'fixed') == liquid]
    t = {(r['spheres'], r['ranks']): r['seconds_per_step'] for r in rows}
    small, large = sorted({r['spheres'] for r in rows})[-2:]
    p = math.log(t[large, 2] / t[small, 2]) / math.log(large / small)
    c = t[large, 2] / large ** p
    k = t[large, 3] / (c * (large / 2) ** p)
    return c, p, k


def predict(c, p, k, n, workers):
    return (k if workers > 1 else 1.0) * c * (n / workers) ** p


def report_model(rows):
    for liquid in sorted({r.get('model', 'fixed') for r in rows}):
        if len({r['spheres'] for r in rows if r.get('model', 'fixed') == liquid}) >= 2:
            report_model_of(rows, liquid)


def report_model_of(rows, liquid):
    c, p, k = model(rows, liquid)
    print('model (%s liquid): a worker\'s step %.3g s * n^%.2f; split into several workers, k = %.2f times that' % (liquid, c, p, k))
    for n, workers in ((10 ** 4, 1), (10 ** 4, 3), (10 ** 5, 15), (10 ** 6, 63)):
        print('  %d spheres on %d ranks: %.3g s per step' % (n, workers + 1, predict(c, p, k, n, workers)))
    for per_worker in (2500, 10000):
        print('  weak, %d spheres per worker: %.3g s per step on any number of workers' % (per_worker, predict(c, p, k, per_worker, 2)))


if len(sys.argv) > 1 and sys.argv[1] == '--worker':
    worker(sys.argv[2], int(sys.argv[3]), sys.argv[4])
elif len(sys.argv) > 1 and sys.argv[1] == '--model':  # the model of the last measurement (the CSV)
    with open(OUT) as fh:
        report_model([numeric(r) for r in csv.DictReader(fh)])
else:
    configs = [configuration(a) for a in sys.argv[1:]] or [('fixed', 1000), ('fixed', 3000)]
    for c in configs:
        land(*c)
    runs = {}
    for _ in range(ROUNDS):
        for c in configs:
            for ranks in (1, 2, 3):
                row = measure(*c, ranks)
                runs.setdefault((c, ranks), []).append(row)
                print(row, flush=True)
    rows = []
    for c in configs:
        serial = min(r['seconds_per_step'] for r in runs[c, 1])
        for ranks in (1, 2, 3):
            done = sorted(runs[c, ranks], key=lambda r: r['seconds_per_step'])
            rows.append(dict(done[0], rounds=len(done), slowest_seconds_per_step=done[-1]['seconds_per_step'],
                             speedup=serial / done[0]['seconds_per_step'],
                             mpy_overhead_per_step=done[0]['seconds_per_step'] - serial if ranks == 2 else ''))
    rows = common.rows_with_earlier(OUT, rows, configuration_key)
    print('wrote', common.write_rows(OUT, rows))
    report_model([numeric(r) for r in rows])
