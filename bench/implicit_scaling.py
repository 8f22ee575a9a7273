# The implicit step against the explicit one as the bed grows: the lagged Cholesky factor and the
# aggregation multigrid (ViscBridgeImplicitSolver.preconditioner, physics.md P15b), on wetted beds
# at μ = 100 Pa·s (Adams–Perchard + slip, bridges from contact), one thread.
#
#   ./yadew run bench/implicit_scaling.py [BED:SIZE ...]   (default: random:1000 lattice:1000 lattice:8000)
#   (the default ~12 min; random:10000 ~15 min the first time, with building the bed; lattice:100000
#   ~16 min and 12 GB).  Writes docs/perf/implicit_scaling.csv for the default beds, else
#   implicit_scaling_<BED><SIZE>[_<BED><SIZE> ...].csv (e.g. implicit_scaling_random10000.csv).
#
# Beds (both kinds for every size):
#   random    the settling scene's column settled dry (viscbridge.scan.dry_bed, cached in
#             bench/.cache; a 10⁴ bed takes several minutes to build the first time), then wetted:
#             every contact a bridge.
#   lattice   a simple cubic lattice of touching spheres on a floor (bench/common.lattice).
# Every sphere gets a random velocity of up to 1 cm/s so that the solver has work at each step.
# Implicit runs at Δt = 5e-6 s (the collision step of these spheres); the explicit step's cost per
# step does not depend on Δt, it is measured at 1e-9 s (stable at any μ).  Each process runs WARM
# steps (first factorisation or multigrid build), then STEPS measured ones; the fastest of ROUNDS
# interleaved rounds is kept, as everywhere in bench/ (common.interleaved).  Peak memory is the
# process's maximum resident set (getrusage), bed and YADE included.
import json
import os
import resource
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
sys.path.insert(0, HERE)
import common  # noqa: E402

R, MU, DT_IMPLICIT, WARM, STEPS, ROUNDS = 0.5e-3, 100.0, 5e-6, 10, 20, 2
CONFIGS = (('explicit', None), ('implicit', 'cholesky'), ('implicit', 'multigrid'))
DEFAULT = [('random', 1000), ('lattice', 1000), ('lattice', 8000)]
LIQUID = dict(viscosity=MU, normalModel='adamsPerchard', tangentialModel='slip')


def random_bed(n, integration):
    from yade import O
    import viscbridge
    O.load(common.bed(n))
    O.interactions.clear()
    O.engines = viscbridge.engines(integration=integration, timeStepper=False, guard=False, **LIQUID)


def lattice_bed(n, integration):
    side = round(n ** (1 / 3))
    common.lattice(side, side, side, radius=R, integration=integration, timeStepper=False, guard=False, viscosity=MU)


def part_column(counter):
    """The CSV column of a solver time counter (timeGather → ms_gather_per_step)."""
    return 'ms_%s_per_step' % counter[4:].lower()


def worker(kind, n, integration, preconditioner, out):
    from yade import O
    import yade.wrapper as yw
    (random_bed if kind == 'random' else lattice_bed)(n, integration)
    common.random_velocities()
    O.dt = DT_IMPLICIT if integration == 'implicit' else 1e-9
    O.trackEnergy = False
    solver = next((e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver)), None)
    if solver:
        solver.preconditioner = preconditioner
    O.run(WARM, True)
    before = (solver.totalIterations, solver.solves, solver.factorisations) if solver else (0, 1, 0)
    times_before = {k: getattr(solver, k) for k in common.SOLVER_TIMES} if solver else {}
    per_step = common.engine_seconds_per_step(STEPS)
    spheres = sum(1 for b in O.bodies if isinstance(b.shape, yw.Sphere))
    row = dict(bed=kind, spheres=spheres, scheme=integration if not solver else 'implicit/' + preconditioner,
               bridges=sum(1 for i in O.interactions if i.isReal and getattr(i.phys, 'bridge', False)),
               ms_per_step=1e3 * per_step, us_per_particle_step=1e6 * per_step / spheres,
               peak_rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
    if solver:
        solves = max(1, solver.solves - before[1])
        row.update(solver_ms_per_step=1e-6 * solver.execTime / STEPS, iterations_per_solve=(solver.totalIterations - before[0]) / solves,
                   refreshes=solver.factorisations - before[2], stored_blocks=solver.factorBlocks, levels=solver.levels,
                   factor_kind=solver.factorKind or '-',
                   **{part_column(k): 1e3 * (getattr(solver, k) - times_before[k]) / STEPS for k in common.SOLVER_TIMES})
    json.dump(row, open(out, 'w'))


def measure(kind, n, integration, preconditioner):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, 'r.json')
        subprocess.run(['yade', '-n', '-j1', '-x', os.path.join(HERE, 'implicit_scaling.py'), '--worker', kind, str(n), integration,
                        preconditioner or '-', out], check=True, capture_output=True)
        return json.load(open(out))


def main(beds):
    rows = []
    for kind, n in beds:
        best = {}
        for _ in range(ROUNDS):
            for integration, pre in CONFIGS:
                r = measure(kind, n, integration, pre)
                print('%-8s %6d spheres %-19s %8.2f ms/step %7.2f µs/particle-step %s' % (
                    kind, r['spheres'], r['scheme'], r['ms_per_step'], r['us_per_particle_step'],
                    '(%.1f iterations/solve, %d refreshes, %d blocks, %s, %.0f MB)' % (
                        r['iterations_per_solve'], r['refreshes'], r['stored_blocks'], r['factor_kind'], r['peak_rss_mb'])
                    if 'levels' in r else ''), flush=True)
                if 'levels' in r:
                    print('    solver ms/step: ' + ', '.join('%s %.2f' % (k[4:].lower(), r[part_column(k)]) for k in common.SOLVER_TIMES), flush=True)
                if r['scheme'] not in best or r['ms_per_step'] < best[r['scheme']]['ms_per_step']:
                    best[r['scheme']] = r
        explicit = best['explicit']['ms_per_step']
        for r in best.values():
            r['versus_explicit'] = r['ms_per_step'] / explicit
            rows.append(r)
    print('\nfastest of %d rounds, one thread, μ = %g Pa·s:' % (ROUNDS, MU))
    for r in rows:
        print('%-8s %6d %-19s %7.2f µs/particle-step  %5.2f× explicit' % (r['bed'], r['spheres'], r['scheme'], r['us_per_particle_step'],
                                                                         r['versus_explicit']))
    keys = list(dict.fromkeys(k for r in rows for k in r))  # the explicit rows have no solver columns
    name = 'implicit_scaling.csv' if beds == DEFAULT else 'implicit_scaling_%s.csv' % '_'.join('%s%d' % b for b in beds)
    print('written', common.write_rows(os.path.join(common.RESULTS, name), [{k: r.get(k, '') for k in keys} for r in rows]))


if len(sys.argv) > 2 and sys.argv[1] == '--worker':
    worker(sys.argv[2], int(sys.argv[3]), sys.argv[4], None if sys.argv[5] == '-' else sys.argv[5], sys.argv[6])
else:
    main([(a.split(':')[0], int(a.split(':')[1])) for a in sys.argv[1:]] or DEFAULT)
