# Wet particles settling through a highly viscous binder: the ViscBridge main example.
#
#   ./yadew run examples/settling.py [OUTPUT_DIRECTORY] [--full | --quick]
#
# 300 glass-like spheres (r = 0.5 mm, ρ = 2500 kg/m³, E = 10 MPa) fall onto the floor of a walled
# column; once two surfaces touch, a liquid bridge (μ = 1 Pa·s, 1 % of a particle's volume) joins
# them and exerts the Adams–Perchard normal force 6πμ r̄² v/S and the 'slip' tangential force, with
# the gap clamped at S_min = 1e-3 r̄.  This is the setting of Washino et al. (2016): with an
# explicit integrator the viscous force decay time t_v = m* S_min/(6πμ r̄²) limits the time step,
# and above the limit the kinetic energy blows up.  The same scene runs four times:
#
#   1. explicit, dt from ViscBridgeTimeStepper (default safety)   -> stable
#   2. explicit, fixed dt = t_v, the no-rebound limit of one pair   -> stable while the bridges are
#      isolated, unstable once particles carry several bridges: a pair criterion is not enough
#   3. explicit, fixed dt = 2.5 t_v (beyond the pair limit 2 t_v)   -> unstable at the first bridges
#   4. implicit viscous forces, dt from the stepper (collision step) -> stable, comes to rest
#
# The explicit runs are followed for the first 0.016 s, through the landing of the column and the
# blow-ups; the implicit run until the particles are at rest (about 0.05 s, 6 000 steps).  Bringing
# the explicit run 1 to rest as well takes 832 000 steps (at rest at 0.052 s, the stepper at ≈ 5-6e-8 s
# once the bridges govern; the first 0.016 s alone take 179 000): --full does it (about 6 min).
# ViscBridgeGuard stops an unstable run when the kinetic energy exceeds what gravity has put in,
# and names the body, the contact and the violated criterion; the summary prints its diagnosis.
# Output: one CSV and one PNG per run, settling.png with the four histories, summary.txt.  Ctrl-C or
# SIGTERM stops the example and saves the history of the run in progress (exit status 130 or 143).
# --quick (or VISCBRIDGE_QUICK=1): 40 spheres and a short time, the same code path (for the tests).
# Expected: runs 1 and 4 stable, run 2 stopped by the guard at t ≈ 0.013 s (network bound violated),
# run 3 at t ≈ 0.0012 s (pair limit violated); about 1 min in all.
import os
import signal
import sys
import time

from yade import O, plot

import viscbridge.scenes as scenes
from viscbridge import criteria

sys.stdout.reconfigure(line_buffering=True)  # the table comes before YADE's log lines, not after
args = [a for a in sys.argv[1:] if a not in ('--quick', '--full')]
quick = '--quick' in sys.argv[1:] or os.environ.get('VISCBRIDGE_QUICK') == '1'
full = '--full' in sys.argv[1:]
out_dir = os.path.abspath(args[0] if args else os.path.join('output', 'settling'))
os.makedirs(out_dir, exist_ok=True)

case = dict(n=300, radius=0.5e-3, density=2500.0, young=1e7, poisson=0.3, friction=0.5, viscosity=1.0,
            sMinRel=1e-3, bridgeVolumeRel=0.01, normalModel='adamsPerchard', tangentialModel='slip', seed=3)
max_duration = 0.08  # s of simulated time; a run ends earlier when its particles have come to rest
explicit_duration = max_duration if full else 0.016
if quick:
    case.update(n=40)
    max_duration = explicit_duration = 0.004

# The planning numbers for this case (viscbridge.criteria works without YADE too).
plan = criteria.critical_dt(case['radius'], case['density'], case['young'], case['poisson'], case['viscosity'],
                            s_min_rel=case['sMinRel'], tangential_model=case['tangentialModel'], coordination=6)
t_v = criteria.viscous_decay_time(case['radius'], case['density'], case['viscosity'],
                                  case['sMinRel'] * case['radius'] / 2)
print(plan)
print('viscous force decay time of an equal pair at S_min: t_v = %.3g s\n' % t_v)

runs = [('stepper', 'explicit, ViscBridgeTimeStepper', dict(dt=None)),
        ('dt_tv', 'explicit, fixed dt = t_v', dict(dt=t_v)),
        ('dt_2.5tv', 'explicit, fixed dt = 2.5 t_v', dict(dt=2.5 * t_v)),
        ('implicit', 'implicit, ViscBridgeTimeStepper', dict(dt=None, integration='implicit'))]


def terminated(signum, frame):
    # SIGTERM (kill, a batch system's time limit) stops the run like Ctrl-C, so that what ran is saved
    raise KeyboardInterrupt('SIGTERM')


signal.signal(signal.SIGTERM, terminated)
histories, summary = {}, []
for key, label, kw in runs:
    print('run %-9s %s ...' % (key, label))
    scene = scenes.settling(cloudFraction=0.25, **dict(case, **kw))
    start = time.time()
    try:
        why, at_rest = scene.settle(max_duration if kw.get('integration') == 'implicit' else explicit_duration)
    except KeyboardInterrupt as stop:
        O.pause()  # the step in progress (and its logger) ends before the history is saved
        O.wait()
        csv_path, _ = scene.save(os.path.join(out_dir, key))
        print('\ninterrupted (%s) in run %s at t = %.4g s: its history so far is in %s%s' % (
            str(stop) or 'Ctrl-C', key, O.time, csv_path, ', the finished runs\' files beside it' if summary else ''))
        sys.exit(143 if str(stop) == 'SIGTERM' else 130)
    wall = time.time() - start
    csv_path, png_path = scene.save(os.path.join(out_dir, key))
    histories[label] = (list(plot.data['t']), list(plot.data['Ek']), list(plot.data['dt']), scene.stopped_at)
    summary.append(dict(key=key, label=label, dt=O.dt, steps=O.iter, time=O.time, ke=scene.kinetic_energy(),
                        released=scene.released_energy(), why=why, at_rest=at_rest, wall=wall, csv=csv_path, png=png_path))

import matplotlib  # noqa: E402
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

fig, (ax, ax_dt) = plt.subplots(2, 1, figsize=(8, 6.4), sharex=True, gridspec_kw=dict(height_ratios=(2, 1)))
# where the runs agree their curves lie on top of each other: the styles tell them apart
styles = (('tab:blue', '-', 2.2), ('tab:orange', '--', 1.6), ('tab:red', '-', 1.6), ('tab:green', ':', 2.2))
for (label, (t, ek, dts, stopped)), (color, line, width) in zip(histories.items(), styles):
    pts = [(x, y) for x, y in zip(t, ek) if y > 0]
    ax.semilogy(*zip(*pts), line, color=color, label=label + (' — stopped: unstable' if stopped is not None else ''),
                linewidth=width)
    if stopped is not None:
        ax.plot([stopped], [pts[-1][1]], 'x', color=color, markersize=9, markeredgewidth=2)
    ax_dt.semilogy(t, dts, line, color=color, linewidth=width)
limits = scenes.log_limits([ek for _, ek, _, _ in histories.values()], decades=6)
ax.set_ylim(*limits)
ax.set_ylabel('total kinetic energy [J]')
ax.set_title('%d spheres settling, μ = %g Pa·s, S_min = 1e-3 r̄ (t_v = %.2g s)' % (case['n'], case['viscosity'], t_v), fontsize=10)
ax.legend(fontsize=8, loc='lower center')
ax.grid(True, which='both', alpha=0.3)
if explicit_duration < max_duration:
    # to the implicit run's rest time at run 1's last dt: a lower estimate (dt keeps falling)
    to_rest = summary[0]['steps'] + (summary[-1]['time'] - summary[0]['time']) / summary[0]['dt']
    ax.text(0.99, 0.97, 'explicit runs shown for the first %g s: to rest, run 1 would need\n' % explicit_duration +
            'over {:,} steps (--full); the implicit run takes {:,}'.format(int(round(to_rest, -3)), summary[-1]['steps']),
            transform=ax.transAxes, ha='right', va='top', fontsize=7.5, color='0.3')
ax_dt.set_ylabel('Δt [s]')
ax_dt.set_xlabel('time [s]')
ax_dt.grid(True, which='both', alpha=0.3)
fig.tight_layout()
png = os.path.join(out_dir, 'settling.png')
fig.savefig(png, dpi=110)

lines = ['%-34s %11s %9s %9s %10s %11s  %s' % ('run', 'last dt [s]', 'steps', 't [s]', 'KE [J]', 'released [J]', 'result')]
for r in summary:
    result = 'UNSTABLE (diagnosis below)' if r['why'] else ('stable, at rest' if r['at_rest'] else 'stable, not yet at rest')
    lines.append('%-34s %11.3g %9d %9.4g %10.3g %11.3g  %s, %.1f s wall' % (
        r['label'], r['dt'], r['steps'], r['time'], r['ke'], r['released'], result, r['wall']))
for r in summary:
    if r['why']:
        lines += ['', '%s — %s' % (r['label'], r['why'])]
with open(os.path.join(out_dir, 'summary.txt'), 'w') as fh:
    fh.write('\n'.join(lines) + '\n')
print('\n' + '\n'.join(lines))
print('\nfiles in %s:' % out_dir)
for r in summary:
    print('  %s, %s' % (os.path.basename(r['csv']), os.path.basename(r['png'])))
print('  settling.png, summary.txt')
