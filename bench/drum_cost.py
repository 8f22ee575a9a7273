# Cost of a drum revolution against the number of spheres: viscbridge.scenes.drum with its defaults
# (1 mm spheres, Fr = 0.05, 15 % of the spheres wetted, μ = 1 Pa·s, implicit, the time stepper on),
# at a drum radius grown with the number of spheres so that the fill stays 0.35 (length 10 r).
#
#   ./yadew run bench/drum_cost.py [N ... | MODEL:N ...] [--models film,fixed] [--rounds 5] [--reland]
#        (default: film liquid at 300, 1000, 3000 and 10 000 spheres, fixed liquid at 300, 1000 and
#        3000; N: every model of --models, MODEL:N one model)
#
# For every liquid model and size, one process builds the drum and lets the bed land: it runs until
# 1.5 × the free-fall time of the highest sphere onto the drum's bottom, sqrt(2 h / g), and saves the
# scene in bench/.cache/drum/ (a bed landed before is reused unless --reland).  Then ROUNDS
# interleaved rounds (every configuration once per round, each in its own `yade -n -j1` process: one
# thread, the process's peak memory its own) load the saved bed, run WARM steps (the implicit
# solver's first factorisation after a load) and measure a window of steps with YADE's engine
# timers (common.engine_seconds_per_step; window_steps(n): about 10⁶ sphere-steps, 100 steps at 10⁴
# spheres).  The fastest round is kept, as everywhere in bench/ (common.interleaved); the slowest is
# written beside it.
#
#   steps per revolution  the drum's period / the mean time step over the window (the stepper's)
#   seconds per step      engine time over the window / its steps
#   hours per revolution  their product / 3600: turning the drum once, one thread
#   bridges               interactions holding a liquid bridge at the end of the window
#   peak RSS              the measuring process's maximum resident set (getrusage; YADE included)
#
# Data: docs/perf/drum_cost.csv.  The default run took about 27 min on the development VM (2 shared
# cores, busy with others' builds): landing the beds 23 min — the 10⁴-sphere film bed 13 min, the
# 3000-sphere fixed one 7.5 min — and the 5 rounds 4 min.  Fixed liquid (every contact a bridge)
# costs about six times the film's per step while landing, so its 10⁴-sphere bed (fixed:10000) is left
# out of the default.
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
sys.path.insert(0, HERE)
import common  # noqa: E402

RADIUS, FILL, LENGTH_RADII, SOLID_FRACTION = 1e-3, 0.35, 10, 0.6
SIZES = (300, 1000, 3000, 10000)
MODELS = ('film', 'fixed')
DEFAULT = [('film', n) for n in SIZES] + [('fixed', n) for n in SIZES if n <= 3000]
ROUNDS, WARM = 5, 5
CACHE = os.path.join(common.CACHE, 'drum')


def drum_radius(n):
    """The drum radius at which `n` spheres fill FILL of the drum at SOLID_FRACTION (scenes.drum's rule, inverted)."""
    length = LENGTH_RADII * RADIUS
    return math.sqrt(n * 4 / 3 * math.pi * RADIUS ** 3 / (FILL * SOLID_FRACTION * math.pi * length))


def window_steps(n):
    """Steps measured per round: about 10⁶ sphere-steps, at least 100."""
    return max(100, int(1e6 / n))


def scene_path(model, n, viscosity=1.0):
    """The landed bed's file; beds at scenes.drum's default viscosity (1 Pa·s) carry none in the name."""
    mu = '' if viscosity == 1.0 else '_mu%g' % viscosity
    return os.path.join(CACHE, '%s_%d%s.yade.gz' % (model, n, mu))


def land(model, n, viscosity, out):
    """Build the drum, let the bed land, save it; write what the measuring runs need to `out`."""
    from yade import O
    import viscbridge.scenes as scenes
    drum = scenes.drum(radius=RADIUS, drumRadius=drum_radius(n), fill=FILL, liquidModel=model, viscosity=viscosity)
    O.trackEnergy = False
    bottom = -drum.params['drumRadius']
    top = max(O.bodies[i].state.pos[2] for i in drum.spheres)
    landing = 1.5 * math.sqrt(2 * (top - bottom) / 9.81)
    start = time.perf_counter()
    drum.run(duration=landing)
    os.makedirs(CACHE, exist_ok=True)
    O.save(scene_path(model, n, viscosity))
    json.dump(dict(spheres=len(drum.spheres), drumRadius=drum.params['drumRadius'], period=drum.period, rpm=drum.params['rpm'],
                   landing_time=landing, landing_steps=O.iter, landing_wall_seconds=time.perf_counter() - start), open(out, 'w'))


def measure(model, n, viscosity, out):
    """One round: load the landed bed, WARM steps, then the window; the row to `out`."""
    from yade import O
    import yade.wrapper as yw
    import viscbridge.measures as measures
    O.load(scene_path(model, n, viscosity))
    landed = dict(spheres=sum(1 for b in O.bodies if isinstance(b.shape, yw.Sphere)), landing_time=O.time, landing_steps=O.iter)
    O.run(WARM, True)
    steps = window_steps(n)
    t0 = O.time
    seconds = common.engine_seconds_per_step(steps)
    json.dump(dict(seconds_per_step=seconds, dt=(O.time - t0) / steps, window_steps=steps, bridges=measures.bridge_count(),
                   peak_rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, **landed), open(out, 'w'))


def period(n):
    """The revolution time of the drum of `n` spheres [s] (scenes.drum's default Froude number)."""
    from viscbridge.scenes.drum import DEFAULT_FROUDE, G
    return 2 * math.pi / math.sqrt(DEFAULT_FROUDE * G / drum_radius(n))


def worker(action, model, n, viscosity=1.0):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, 'r.json')
        done = subprocess.run(['yade', '-n', '-j1', '-x', os.path.join(HERE, 'drum_cost.py'), '--' + action, model, str(n), repr(viscosity), out],
                              capture_output=True, text=True)
        if done.returncode != 0 or not os.path.exists(out):
            raise RuntimeError('drum_cost %s %s %d failed:\n%s' % (action, model, n, done.stdout[-3000:] + done.stderr[-3000:]))
        return json.load(open(out))


def ensure_landed(model, n, viscosity=1.0, reland=False):
    """The bed of `n` spheres with `model` liquid at `viscosity` landed and saved, unless it was before."""
    path = scene_path(model, n, viscosity)
    if reland or not os.path.exists(path):
        r = worker('land', model, n, viscosity)
        print('%-5s %6d spheres μ=%g landed: %d steps, %.3f s simulated, %.0f s wall' % (
            model, r['spheres'], viscosity, r['landing_steps'], r['landing_time'], r['landing_wall_seconds']), flush=True)
    else:
        print('%-5s %6d spheres μ=%g: landed bed reused (%s; --reland to make it anew)' % (model, n, viscosity, path), flush=True)


def main(configs, rounds, reland=False):
    began = time.perf_counter()
    for c in configs:
        ensure_landed(*c, reland=reland)
    landed = {}
    samples = {c: [] for c in configs}
    for r in range(rounds):
        for c in configs:
            s = worker('measure', *c)
            samples[c].append(s)
            landed[c] = dict(spheres=s['spheres'], landing_time=s['landing_time'], drumRadius=drum_radius(c[1]), period=period(c[1]))
            landed[c]['rpm'] = 60 / landed[c]['period']
            print('round %d %-5s %6d spheres: %.4f s/step (dt %.3g s, %d bridges, %.0f MB)' % (
                r + 1, c[0], s['spheres'], s['seconds_per_step'], s['dt'], s['bridges'], s['peak_rss_mb']), flush=True)
    rows = []
    for c in configs:
        best = min(samples[c], key=lambda s: s['seconds_per_step'])
        slowest = max(s['seconds_per_step'] for s in samples[c])
        steps_per_rev = landed[c]['period'] / best['dt']
        rows.append(dict(liquidModel=c[0], spheres=landed[c]['spheres'], drum_radius_mm=1e3 * landed[c]['drumRadius'],
                         rpm=landed[c]['rpm'], period_s=landed[c]['period'], dt=best['dt'], steps_per_revolution=steps_per_rev,
                         seconds_per_step=best['seconds_per_step'], seconds_per_step_slowest=slowest,
                         hours_per_revolution=steps_per_rev * best['seconds_per_step'] / 3600, bridges=best['bridges'],
                         peak_rss_mb=max(s['peak_rss_mb'] for s in samples[c]), window_steps=best['window_steps'], rounds=rounds,
                         landing_time_s=landed[c]['landing_time']))
    print('\ncost of a revolution, one thread, fastest of %d interleaved rounds:' % rounds)
    print('%-5s %7s %12s %10s %10s %9s %8s' % ('model', 'spheres', 'steps/rev', 's/step', 'h/rev', 'bridges', 'RSS MB'))
    for r in rows:
        print('%-5s %7d %12.0f %10.4f %10.3f %9d %8.0f' % (r['liquidModel'], r['spheres'], r['steps_per_revolution'],
                                                         r['seconds_per_step'], r['hours_per_revolution'], r['bridges'], r['peak_rss_mb']))
    print('written', common.write_rows(os.path.join(common.RESULTS, 'drum_cost.csv'), rows))
    print('bench took %.1f min' % ((time.perf_counter() - began) / 60))


if os.path.basename(sys.argv[0]) != 'drum_cost.py':
    pass  # imported (tests, another bench): nothing to run
elif len(sys.argv) > 1 and sys.argv[1] in ('--land', '--measure'):
    (land if sys.argv[1] == '--land' else measure)(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5])
else:
    args, sizes, models, rounds, reland = sys.argv[1:], [], list(MODELS), ROUNDS, False
    while args:
        a = args.pop(0)
        if a == '--models':
            models = args.pop(0).split(',')
        elif a == '--rounds':
            rounds = int(args.pop(0))
        elif a == '--reland':
            reland = True
        else:
            sizes.append(a)
    configs = []
    for a in sizes:
        model, _, n = a.rpartition(':')
        configs += [(model, int(n))] if model else [(m, int(n)) for m in models]
    main(configs or DEFAULT, rounds, reland)
