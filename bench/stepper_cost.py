# What ViscBridgeTimeStepper costs: the step time with the stepper against the same scene at the
# same fixed Δt without it, in one process, fastest of interleaved rounds (docs/performance.md §2).
#
#   ./yadew run bench/stepper_cost.py [LATTICE_SIDE]      (default 46: a 46³ ≈ 10⁵-sphere lattice; ~10 min)
#
# Scenes: the study's wetted bed (300 spheres, every contact a bridge at S_min, μ = 1 Pa·s), and a
# periodic simple-cubic lattice of LATTICE_SIDE³ spheres, every neighbour pair bridged at S_min/2.
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # yade -x: __file__ is yade's own
import common  # noqa: E402
from yade import O, utils  # noqa: E402
import yade.wrapper as yw  # noqa: E402

import viscbridge  # noqa: E402
import viscbridge.scan as scan  # noqa: E402

R = 0.5e-3
side = int(sys.argv[1]) if len(sys.argv) > 1 else 46


def study_bed():
    case = scan.normalize_case(dict(n=300, seed=5, viscosity=1.0))
    trial = scan._Trial(case, scan.dry_bed(case, common.CACHE))
    trial.prepare()


def lattice():
    O.reset()
    O.periodic = True
    gap = 0.5e-3 * R / 2
    a = 2 * R + gap
    O.cell.setBox(side * a, side * a, side * a)
    mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
    O.bodies.append([utils.sphere(((i + 0.5) * a, (j + 0.5) * a, (k + 0.5) * a), R, material=mat)
                     for i in range(side) for j in range(side) for k in range(side)])
    O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=1.0, formationDistance=2 * gap, minRadius=R, guard=False)
    O.dt = 1e-12


SCENES = {'study bed (300 spheres)': (study_bed, 2000), 'lattice (%d spheres)' % side ** 3: (lattice, 120)}
rows = []
for name, (build, steps) in SCENES.items():
    build()
    O.run(100, True)  # bridges in place, the stepper settled on its dt and interval
    saved = os.path.join(common.CACHE, 'stepper_cost.yade.gz')
    os.makedirs(common.CACHE, exist_ok=True)
    O.save(saved)

    def measure(config):
        O.load(saved)
        ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
        if config == 'stepper off':
            ts.dead = True  # the same engines, the same Δt, the stepper skipped
        O.run(60, True)  # the stepper's warm start is not saved: let it find its mode again
        return common.engine_seconds_per_step(steps)

    best, _ = common.interleaved(['stepper on', 'stepper off'], measure, rounds=3 if side > 20 and 'lattice' in name else 5)
    O.load(saved)
    ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
    bridges = sum(1 for i in O.interactions if i.isReal and i.phys.bridge)
    ratio = best['stepper on'] / best['stepper off']
    print('%s: %d bridges, %.1f µs/step with the stepper, %.1f without: cost %.2f %% (update interval %d)'
          % (name, bridges, best['stepper on'] * 1e6, best['stepper off'] * 1e6, 100 * (ratio - 1), ts.updateInterval), flush=True)
    rows.append(dict(scene=name, bridges=bridges, microseconds_with=best['stepper on'] * 1e6,
                     microseconds_without=best['stepper off'] * 1e6, cost_percent=100 * (ratio - 1), update_interval=ts.updateInterval))
print('written', common.write_rows(os.path.join(common.RESULTS, 'stepper_cost.csv'), rows))
