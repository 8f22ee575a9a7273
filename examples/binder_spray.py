# Binder sprayed onto a falling cloud of dry particles: where the liquid goes.
#
#   ./yadew run examples/binder_spray.py [OUTPUT_DIRECTORY] [--quick]
#
# 300 dry spheres (r = 0.5 mm) fall through a spray zone (the upper half of a walled column) onto
# its floor.  For the first 20 ms a nozzle above sprays a binder of viscosity 10 Pa·s straight down at
# a constant rate, 2 % of the particles' volume in all: the droplets wet the particles in the zone
# they meet first, each in proportion to the area it shows the nozzle (docs/physics.md L6).  The liquid is conserved (liquidModel='film', docs/physics.md §11): it lands in
# the particles' films; where two wet particles meet, a bridge takes its volume from their films
# (at most 1 % of a particle's volume); a bridge that breaks gives it back.  The viscous forces are
# implicit (the time step is the collision step, not the viscous one).
#
# Output (OUTPUT_DIRECTORY, default output/binder_spray): binder_spray.csv (time, liquid sprayed,
# in films, in bridges, CoV of the liquid per particle, bridges) and binder_spray.png: the liquid
# budget over time (the total follows the spray exactly) and the uniformity of the liquid per
# particle.  Expected (300 spheres, measured): the sprayed volume all in films and bridges (relative
# error 8e-16), 369 bridges holding 56 % of it once the bed has formed; the CoV of the liquid per
# particle stays near 1.1–1.4: the spray wets the side of the cloud it sees, and bridges spread it
# to the others only where they touch.
# --quick (or VISCBRIDGE_QUICK=1): 60 spheres, 25 ms (the tests); the full run takes about 10 s.
import os
import sys

from yade import O, plot

import viscbridge.liquid as liquid
import viscbridge.scenes as scenes

sys.stdout.reconfigure(line_buffering=True)
args = [a for a in sys.argv[1:] if a != '--quick']
quick = '--quick' in sys.argv[1:] or os.environ.get('VISCBRIDGE_QUICK') == '1'
out_dir = os.path.abspath(args[0] if args else os.path.join('output', 'binder_spray'))
os.makedirs(out_dir, exist_ok=True)

n, radius, spray_time = (60, 0.5e-3, 0.01) if quick else (300, 0.5e-3, 0.02)
duration = 0.025 if quick else 0.06
scene = scenes.settling(n=n, radius=radius, viscosity=10.0, integration='implicit', liquidModel='film',
                        bridgeVolumeRel=0.01, seed=3)
p = scene.params
spheres = [b for b in O.bodies if b.dynamic]
particle_volume = sum(4 / 3 * 3.141592653589793 * b.shape.radius ** 3 for b in spheres)
binder = 0.02 * particle_volume  # m³ sprayed in all
zone = ((0, 0, p['height'] / 2), (p['width'], p['width'], 2 * p['height']))
O.engines = O.engines + [liquid.spray(rate=binder / spray_time, box=zone, start=0, end=spray_time, iterPeriod=20)]
spray = liquid.sprays()[-1]
print('%d spheres, %.3g m³ of binder sprayed over %.3g s onto z > %.3g m' % (n, binder, spray_time, zone[0][2]))

rows = []


def log():
    spread = liquid.distribution()
    rows.append(dict(t=O.time, sprayed=spray.sprayed, films=liquid.in_films(), bridges=liquid.in_bridges(),
                     cov=spread.cov, count=scene.bridges()))


log()
while O.time < duration:
    why = scene.run(duration=duration / 40, points=5)
    log()
    if why:
        print('stopped:', why)
        break

last = rows[-1]
error = abs(last['films'] + last['bridges'] - spray.delivered) / spray.delivered
print('sprayed %.4g m³; in films %.4g, in bridges %.4g (relative error of the total %.2g); %d bridges; CoV %.3f'
      % (spray.delivered, last['films'], last['bridges'], error, last['count'], last['cov']))

with open(os.path.join(out_dir, 'binder_spray.csv'), 'w') as fh:
    fh.write('t_s,sprayed_m3,in_films_m3,in_bridges_m3,liquid_cov,bridges\n')
    for r in rows:
        fh.write('%.6g,%.6g,%.6g,%.6g,%.6g,%d\n' % (r['t'], r['sprayed'], r['films'], r['bridges'], r['cov'], r['count']))

import matplotlib  # noqa: E402
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

t = [1e3 * r['t'] for r in rows]
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
scale = 1e9  # mm³
ax1.plot(t, [scale * r['sprayed'] for r in rows], 'k--', lw=2.5, label='sprayed')
ax1.plot(t, [scale * (r['films'] + r['bridges']) for r in rows], 'C3-', lw=1.2, label='films + bridges (total)')
ax1.plot(t, [scale * r['films'] for r in rows], 'C0-', label='in films')
ax1.plot(t, [scale * r['bridges'] for r in rows], 'C2-', label='in bridges')
ax1.axvspan(0, 1e3 * spray_time, color='0.9', zorder=0, label='spraying')
ax1.set_xlabel('time [ms]')
ax1.set_ylabel('liquid [mm³]')
ax1.set_title('Where the binder is (conserved: total = sprayed)')
ax1.legend(loc='upper left', fontsize=8)
ax2.plot(t, [r['cov'] for r in rows], 'C1-', label='CoV of liquid per particle')
ax2.set_xlabel('time [ms]')
ax2.set_ylabel('coefficient of variation')
ax2.set_ylim(bottom=0)
ax2b = ax2.twinx()
ax2b.plot(t, [r['count'] for r in rows], 'C7:', label='bridges')
ax2b.set_ylabel('bridges')
ax2b.grid(False)
ax2.set_title('Uniformity of the liquid (lower = more uniform)')
lines = ax2.get_lines() + ax2b.get_lines()
ax2.legend(lines, [line.get_label() for line in lines], loc='center right', fontsize=8)
fig.suptitle('%d spheres falling through a spray of 10 Pa·s binder (%.0f %% of their volume)' % (n, 2), fontsize=11)
fig.tight_layout()
fig.savefig(os.path.join(out_dir, 'binder_spray.png'), dpi=110)
print('written', os.path.join(out_dir, 'binder_spray.csv'), os.path.join(out_dir, 'binder_spray.png'))
