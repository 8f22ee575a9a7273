# Wet particles settling through a highly viscous binder: the ViscBridge main example.
#
#   ./yadew run examples/settling.py [OUTPUT_DIRECTORY]          (about a minute on 2 cores)
#
# 300 glass-like spheres (r = 0.5 mm, ρ = 2500 kg/m³, E = 10 MPa) settle under gravity in a walled
# column; once two surfaces touch, a liquid bridge (μ = 1 Pa·s, 1 % of a particle's volume) joins
# them and exerts the Adams–Perchard normal force 6πμ r̄² v/S and the 'slip' tangential force, with
# the gap clamped at S_min = 1e-3 r̄.  This is the setting of Washino et al. (2016): with an
# explicit integrator the viscous force decay time t_v = m* S_min/(6πμ r̄²) limits the time step,
# and above the limit the kinetic energy blows up.  The same scene runs three times:
#
#   1. dt from ViscBridgeTimeStepper at its default safety     -> stable
#   2. fixed dt = t_v of an equal pair at S_min                -> stable, no spurious rebound
#   3. fixed dt = 2.5 t_v (beyond the pair limit 2 t_v)        -> blows up as soon as bridges form
#
# Each run logs the total kinetic energy against time; a run stops early when the kinetic energy
# exceeds the potential energy released so far (energy the physics cannot have produced).
# Output: one CSV per run and settling.png with the three kinetic-energy histories.
import os
import sys
import time

from yade import O, plot

import viscbridge.scenes as scenes
from viscbridge import criteria

out_dir = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join('output', 'settling'))
os.makedirs(out_dir, exist_ok=True)

case = dict(n=300, radius=0.5e-3, density=2500.0, young=1e7, poisson=0.3, friction=0.5, viscosity=1.0,
            sMinRel=1e-3, bridgeVolumeRel=0.01, normalModel='adamsPerchard', tangentialModel='slip', seed=3)
duration = 0.012  # s of simulated time

# The planning numbers for this case (viscbridge.criteria works without YADE too).
plan = criteria.critical_dt(case['radius'], case['density'], case['young'], case['poisson'], case['viscosity'],
                            s_min_rel=case['sMinRel'], tangential_model=case['tangentialModel'], coordination=6)
t_v = criteria.viscous_decay_time(case['radius'], case['density'], case['viscosity'],
                                  case['sMinRel'] * case['radius'] / 2)
print(plan)
print('viscous force decay time of an equal pair at S_min: t_v = %.3g s' % t_v)

runs = [('stepper', 'ViscBridgeTimeStepper, default safety', None),
        ('dt_tv', 'fixed dt = t_v', t_v),
        ('dt_2.5tv', 'fixed dt = 2.5 t_v', 2.5 * t_v)]
histories, summary = {}, []
for key, label, dt in runs:
    scene = scenes.settling(dt=dt, **case)
    start = time.time()
    why = scene.run(duration=duration)
    wall = time.time() - start
    csv_path, _ = scene.save(os.path.join(out_dir, key))
    histories[label] = (list(plot.data['t']), list(plot.data['Ek']))
    summary.append((label, O.dt, O.iter, O.time, scene.kinetic_energy(), scene.released_energy(), why, wall, csv_path))

import matplotlib  # noqa: E402
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(7.5, 4.5))
peak = max(max(ek) for _, ek in histories.values())
for (label, (t, ek)), style in zip(histories.items(), ('-', '--', '-')):
    ax.semilogy(t, [max(e, 1e-30) for e in ek], style, label=label, linewidth=1.6)
ax.set_ylim(peak * 1e-5, peak * 3)
ax.set_xlabel('time [s]')
ax.set_ylabel('total kinetic energy [J]')
ax.set_title('300 spheres settling, μ = 1 Pa·s, S_min = 1e-3 r̄ (t_v = %.2g s)' % t_v, fontsize=10)
ax.legend()
ax.grid(True, which='both', alpha=0.3)
fig.tight_layout()
png = os.path.join(out_dir, 'settling.png')
fig.savefig(png, dpi=110)

print('\n%-40s %11s %8s %10s %11s %11s  %s' % ('run', 'last dt [s]', 'steps', 'time [s]', 'KE [J]', 'released [J]', 'result'))
for label, dt, steps, t, ek, released, why, wall, _ in summary:
    print('%-40s %11.3g %8d %10.4g %11.3g %11.3g  %s (%.1f s wall)' % (
        label, dt, steps, t, ek, released, 'UNSTABLE: ' + why if why else 'stable', wall))
print('\nCSV files:')
for row in summary:
    print('  ' + row[-1])
print('plot:\n  ' + png)
