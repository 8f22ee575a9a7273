# The cost of the law itself: step time on the same settled packing for YADE's dry Hertz-Mindlin
# law, ViscBridge's law with every viscous effect off, each effect alone, all effects, and YADE's
# implicit lubrication law, as ratios to the dry YADE step measured in the same process.
#
#   ./yadew run bench/law_cost.py [N ...]        (default: 1000 and 4000 spheres; 1 thread; 1–3 min per size)
#   ./yadew run -j2 bench/law_cost.py 1000       (the same with 2 threads)
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # yade -x: __file__ is yade's own
import common  # noqa: E402
from yade import O  # noqa: E402

CONFIGS = common.CONFIGS


def isolated(path, config, steps, attempts=3):
    """Seconds per step of `config` measured in a separate yade process: YADE's
    Law2_ScGeom_ImplicitLubricationPhys sometimes aborts the whole process ('Initial point
    problem', thrown inside its OpenMP loop) when run after other configurations in one process."""
    import json
    import subprocess
    import tempfile
    for _ in range(attempts):
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, 'r.json')
            done = subprocess.run(['yade', '-n', '-j%d' % O.numThreads, '-x', os.path.abspath(sys.argv[0]), '--worker', path,
                                   config, str(steps), out], capture_output=True)
            if done.returncode == 0 and os.path.exists(out):
                return json.load(open(out))['seconds']
    return float('nan')


if len(sys.argv) > 1 and sys.argv[1] == '--worker':
    _, _, bed_path, config, steps, out = sys.argv[:6]
    common.load(bed_path, config)
    O.run(20, True)
    import json
    with open(out, 'w') as fh:
        json.dump(dict(seconds=common.engine_seconds_per_step(int(steps))), fh)
    sys.exit(0)
sizes = [int(a) for a in sys.argv[1:]] or [1000, 4000]
rows = []
for n in sizes:
    path = common.bed(n)
    steps = max(100, 400000 // n)

    def measure(config):
        if config == 'yade_implicit_lubrication':
            seconds = isolated(path, config, steps)
        else:
            common.load(path, config)
            O.run(20, True)  # interactions and bridges in place
            seconds = common.engine_seconds_per_step(steps)
            # the share of ViscBridgeForceSum (the law's forces added in an order no thread count changes)
            summing = sum(e.execTime for e in O.engines if type(e).__name__ == 'ViscBridgeForceSum')
            shares.setdefault(config, []).append(summing / max(sum(e.execTime for e in O.engines), 1))
        print('  %d spheres, %-26s %10.1f µs/step' % (n, config, seconds * 1e6), flush=True)
        return seconds

    shares = {}
    median, samples = common.interleaved(CONFIGS, measure)
    common.load(path, 'vb_all')
    O.run(20, True)
    bridges = sum(1 for i in O.interactions if i.isReal and i.phys.bridge)
    base = median['yade_mindlin']
    print('\n%d spheres, %d bridges, %d threads, %d steps per sample, fastest of 7 interleaved rounds' % (n, bridges, O.numThreads, steps))
    print('%-28s %12s %8s' % ('configuration', 'µs/step', 'ratio'))
    for c in CONFIGS:
        print('%-28s %12.1f %8.3f' % (c, median[c] * 1e6, median[c] / base), flush=True)
        rows.append(dict(spheres=n, threads=O.numThreads, configuration=c, microseconds_per_step=median[c] * 1e6,
                         ratio_to_yade_mindlin=median[c] / base, contacts=bridges,
                         slowest_microseconds_per_step=max(x for x in samples[c] if x == x) * 1e6, rounds=len(samples[c]),
                         force_sum_share_min=min(shares.get(c, [0])), force_sum_share_max=max(shares.get(c, [0]))))
out = common.write_rows(os.path.join(common.RESULTS, 'law_cost_%dthreads.csv' % O.numThreads), rows)
print('\nwritten', out)
