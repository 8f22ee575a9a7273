# The implicit solver on 1 and 2 threads: a wetted bed of 10⁴ spheres (a 41 × 41 × 6 lattice of
# touching spheres, r = 0.5 mm, on a floor, every neighbour contact a bridge, μ = 100 Pa·s,
# Adams–Perchard + slip), integration='implicit' at Δt = 5e-6 s, disturbed by random velocities of
# up to 1 cm/s so that the solver has work at every step.
#
#   ./yadew run bench/implicit_threads.py [SIDE LAYERS [ROUNDS]]   (default 41 6 3: ~5 min; one yade
#                                                                   process per run; 46 46 2: 97 336
#                                                                   spheres, ~15 min, 13 GB)
#
# Each process runs 20 steps (the first factorisation and analysis) and then measures STEPS steps;
# the solver's engine time per step (YADE's timers) and its own split are compared, fastest of
# ROUNDS interleaved rounds of 1 and 2 threads.
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
sys.path.insert(0, HERE)
import common  # noqa: E402

R, STEPS = 0.5e-3, 40
_sizes = [int(a) for a in sys.argv[1:] if a.isdigit()]
SIDE, LAYERS, ROUNDS = (_sizes + [41, 6, 3][len(_sizes):])[:3]
if sys.argv[1:2] == ['--worker']:
    SIDE, LAYERS = int(sys.argv[3]), int(sys.argv[4])


def bed():
    from yade import O
    common.lattice(SIDE, SIDE, LAYERS, radius=R, viscosity=100.0, integration='implicit', timeStepper=False, guard=False)
    common.random_velocities()
    O.dt = 5e-6


def worker(out):
    from yade import O
    import yade.wrapper as yw
    bed()
    O.run(20, True)
    solver = next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver))
    before = {k: getattr(solver, k) for k in common.SOLVER_TIMES}
    iterations0, factorisations0 = solver.totalIterations, solver.factorisations
    O.timingEnabled = True
    solver.execTime = 0
    O.run(STEPS, True)
    json.dump(dict(threads=O.numThreads, spheres=len(O.bodies) - 1, bridges=solver.bridges, factorBlocks=solver.factorBlocks,
                   solver_seconds_per_step=solver.execTime * 1e-9 / STEPS,
                   iterations_per_step=(solver.totalIterations - iterations0) / STEPS,
                   factorisations=solver.factorisations - factorisations0,
                   **{k: (getattr(solver, k) - before[k]) / STEPS for k in common.SOLVER_TIMES}), open(out, 'w'))


if len(sys.argv) > 2 and sys.argv[1] == '--worker':
    worker(sys.argv[2])
else:
    best = {}
    for _ in range(ROUNDS):
        for threads in (1, 2):
            with tempfile.TemporaryDirectory() as tmp:
                out = os.path.join(tmp, 'r.json')
                subprocess.run(['yade', '-n', '-j%d' % threads, '-x', os.path.join(HERE, 'implicit_threads.py'), '--worker', out, str(SIDE), str(LAYERS)],
                               check=True, capture_output=True)
                r = json.load(open(out))
            print('%d thread(s): solver %.2f ms/step (%.2f CG iterations/step, %d factorisations)' % (
                threads, 1e3 * r['solver_seconds_per_step'], r['iterations_per_step'], r['factorisations']), flush=True)
            if threads not in best or r['solver_seconds_per_step'] < best[threads]['solver_seconds_per_step']:
                best[threads] = r
    rows = [best[1], best[2]]
    for r in rows:
        r['speedup'] = best[1]['solver_seconds_per_step'] / r['solver_seconds_per_step']
    print('\n%d spheres, %d bridges, factor %d blocks; fastest of %d rounds, ms per step:' % (
        best[1]['spheres'], best[1]['bridges'], best[1]['factorBlocks'], ROUNDS))
    for r in rows:
        print('%d thread(s): solver %.2f (%s); speed-up %.2f' % (
            r['threads'], 1e3 * r['solver_seconds_per_step'], ', '.join('%s %.2f' % (k[4:], 1e3 * r[k]) for k in common.SOLVER_TIMES), r['speedup']))
    name = 'implicit_threads.csv' if (SIDE, LAYERS) == (41, 6) else 'implicit_threads_%dx%dx%d.csv' % (SIDE, SIDE, LAYERS)
    print('written', common.write_rows(os.path.join(common.RESULTS, name), rows))
