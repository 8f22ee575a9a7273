# Scaling: time per particle-step from 1e3 to 1e5 particles, and the speed-up on 2 threads.
# Cubic lattices of touching spheres (r = 0.5 mm) on a floor, every neighbour contact a bridge
# (μ = 1 Pa·s, Adams–Perchard + slip), with the full viscbridge.engines() list (time stepper and
# guard included), explicit integration.
#
#   ./yadew run bench/scaling.py                 (drives one yade process per size and thread count; ~15 min)
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
sys.path.insert(0, HERE)
import common  # noqa: E402

R = 0.5e-3


def lattice(n_side, mu=1.0, integration='explicit'):
    common.lattice(n_side, n_side, n_side, radius=R, viscosity=mu, integration=integration)


def worker(n_side, steps, config):
    from yade import O
    lattice(n_side)
    if config == 'yade_mindlin':  # YADE's own dry law on the same lattice, for comparison
        O.interactions.clear()
        O.engines = common.engines('yade_mindlin')
    O.run(10, True)
    per_step = common.engine_seconds_per_step(steps)
    engines = {type(e).__name__ if not e.label else e.label: e.execTime * 1e-9 / steps for e in O.engines}
    n = len(O.bodies) - 1
    return dict(configuration=config, spheres=n, threads=O.numThreads, steps=steps, seconds_per_step=per_step,
                microseconds_per_particle_step=per_step / n * 1e6,
                bridges=sum(1 for i in O.interactions if i.isReal and getattr(i.phys, 'bridge', False)), engines=engines)


if len(sys.argv) > 2 and sys.argv[1] == '--worker':
    result = worker(int(sys.argv[2]), int(sys.argv[3]), sys.argv[5])
    json.dump(result, open(sys.argv[4], 'w'))
else:
    rows = []
    for n_side in (10, 20, 30, 47):
        steps = max(20, 2000000 // n_side ** 3)
        for config, threads in (('viscbridge', 1), ('viscbridge', 2), ('yade_mindlin', 1), ('yade_mindlin', 2)):
            with tempfile.TemporaryDirectory() as tmp:
                out = os.path.join(tmp, 'r.json')
                subprocess.run(['yade', '-n', '-j%d' % threads, '-x', os.path.join(HERE, 'scaling.py'), '--worker',
                                str(n_side), str(steps), out, config], check=True, capture_output=True)
                r = json.load(open(out))
            rows.append(r)
            print('%-12s %7d spheres %d thread(s): %8.3f µs per particle-step (%d bridges; %s)' % (
                config, r['spheres'], threads, r['microseconds_per_particle_step'], r['bridges'],
                ', '.join('%s %.0f%%' % (k, 100 * v / r['seconds_per_step']) for k, v in r['engines'].items())), flush=True)
    for r in rows:
        one = next(x for x in rows if x['spheres'] == r['spheres'] and x['threads'] == 1 and x['configuration'] == r['configuration'])
        r['speedup'] = one['seconds_per_step'] / r['seconds_per_step']
        r['engines'] = json.dumps(r['engines'])
    for config in ('viscbridge', 'yade_mindlin'):
        mine = [r for r in rows if r['threads'] == 1 and r['configuration'] == config]
        print('%s, per particle-step relative to 1000 spheres (1 thread): ' % config + ', '.join(
            '%d: %.2f' % (r['spheres'], r['microseconds_per_particle_step'] / mine[0]['microseconds_per_particle_step']) for r in mine))
    print('speed-up on 2 threads: ' + ', '.join('%d: %.2f' % (r['spheres'], r['speedup']) for r in rows if r['threads'] == 2))
    print('written', common.write_rows(os.path.join(common.RESULTS, 'scaling.csv'), rows))
