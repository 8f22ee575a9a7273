# How many steps ViscBridgeTimeStepper (default safety) makes a run take, on the two scenes of
# issue 12's target:
#  - example: run 1 of examples/settling.py (300 spheres landing in a walled column, μ = 1 Pa·s,
#    explicit) followed until the particles are at rest, as `examples/settling.py --full` does;
#  - study:   the wetted bed of the critical-Δt study (docs/study.md: 300 spheres, every contact a
#    bridge at S_min, random velocities of 1 cm/s, μ = 1 Pa·s) for STUDY_TIME of simulated time.
#
#   ./yadew run bench/stepper_steps.py [OUT.json [CACHE_DIR [SCENE ...]]]   (~6 min with the spectral stepper)
#
# SCENE: 'example' and/or 'study' (default both).
#
# For each: steps, simulated and wall time, kinetic energy, and the final positions (so that two
# builds can be compared for the same outcome); for the example also the logged row at the end of
# its default explicit window (0.016 s).  The script uses only viscbridge.scenes and viscbridge.scan
# as they were before issue 12, so that it runs against that build too (docs/performance.md, "Other benchmarks").
import json
import os
import sys
import time

from yade import O, plot

import viscbridge.scenes as scenes

# the case of examples/settling.py, written out: the build before issue 12 has no shared copy of it
EXAMPLE = dict(n=300, radius=0.5e-3, density=2500.0, young=1e7, poisson=0.3, friction=0.5, viscosity=1.0,
               sMinRel=1e-3, bridgeVolumeRel=0.01, normalModel='adamsPerchard', tangentialModel='slip', seed=3)
MAX_DURATION, WINDOW = 0.08, 0.016  # as examples/settling.py: --full, and its default explicit window
STUDY_TIME = 2e-4
# the settled dry bed of the study is built once and cached (another build may need its own)
CACHE = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(os.path.abspath(sys.argv[0])), '.cache')


def positions():
    return {b.id: tuple(b.state.pos) for b in O.bodies if b.dynamic}


def example():
    scene = scenes.settling(cloudFraction=0.25, **EXAMPLE)
    start = time.time()
    why, at_rest = scene.settle(MAX_DURATION)  # as --full does: to rest (or MAX_DURATION)
    wall = time.time() - start
    k = next(i for i, t in enumerate(plot.data['t']) if t >= WINDOW * (1 - 1e-9))  # the first row at or after it
    window = dict((key, plot.data[key][k]) for key in ('t', 'iter', 'dt', 'Ek'))
    return dict(window=window, steps=O.iter, time=O.time, dt=O.dt, wall=wall, at_rest=at_rest, unstable=why,
                ke=scene.kinetic_energy(), released=scene.released_energy(), positions=positions())


def study():
    import viscbridge.scan as scan
    case = scan.normalize_case(dict(n=300, seed=5, viscosity=1.0))
    trial = scan._Trial(case, scan.dry_bed(case, CACHE))
    trial.prepare()  # wetted, perturbed, with the engines of viscbridge.engines() (stepper included)
    start, iter0, time0 = time.time(), O.iter, O.time
    O.stopAtTime = O.time + STUDY_TIME
    O.run(-1, True)
    ke, released = trial.measures()
    return dict(steps=O.iter - iter0, time=O.time - time0, dt=O.dt, wall=time.time() - start, ke=ke, ke0=trial.ke0, released=released,
                positions=positions())


scenes_asked = sys.argv[3:] or ['example', 'study']
result = dict((name, dict(example=example, study=study)[name]()) for name in scenes_asked)
for name, r in result.items():
    print(name, json.dumps(dict((k, v) for k, v in r.items() if k != 'positions')))
if len(sys.argv) > 1:
    json.dump(result, open(sys.argv[1], 'w'))
