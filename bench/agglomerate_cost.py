"""Cost of viscbridge.agglomerates() and of one AgglomerateHistory row on large random beds, against
the cost of one time step of the same scene.

    ./yadew run bench/agglomerate_cost.py [N ...]       # default: 10000 100000; about 2 min

A bed of N spheres (r = 0.5 mm ± 10 %, jittered cubic lattice of pitch 2.1 r: random gaps and a
coordination of about 5) in a box, liquid bridges formed within formationDistance = 0.3 r.  It
reports the fastest of three calls, split into reading the bridges off O (Python over
O.interactions) and the components (scipy), and the step time from YADE's engine timers.
"""
import sys
import time

import numpy
from yade import O, utils
import yade.wrapper as yw

import viscbridge
from viscbridge.analysis import agglomerates as ag
from viscbridge.analysis.agglomerate_history import AgglomerateHistory

R = 0.5e-3


def random_bed(n, seed=3):
    O.reset()
    rng = numpy.random.default_rng(seed)
    side = int(round(n ** (1 / 3.0)))
    pitch = 2.1 * R
    mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
    grid = numpy.stack(numpy.meshgrid(*[numpy.arange(side)] * 3, indexing='ij'), -1).reshape(-1, 3)[:n]
    centres = (grid + 0.5) * pitch + rng.uniform(-0.04, 0.04, size=(len(grid), 3)) * R
    radii = R * rng.uniform(0.9, 1.0, size=len(grid))
    O.bodies.append([utils.sphere(tuple(c), float(r), material=mat) for c, r in zip(centres, radii)])
    O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=10.0, formationDistance=0.3 * R, timeStepper=False,
                                   guard=False, minRadius=0.9 * R)
    O.dt = 1e-7
    O.run(1, True)


def fastest(call, rounds=3):
    best = float('inf')
    for _ in range(rounds):
        start = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - start)
    return best


def step_time(steps=5):
    O.timingEnabled = True
    for e in O.engines:
        e.execTime = 0
    O.run(steps, True)
    return sum(e.execTime for e in O.engines) * 1e-9 / steps


def measure(n):
    random_bed(n)
    members, edges, masses, liquid = ag.edges_of_scene()
    read = fastest(lambda: ag.edges_of_scene())
    components = fastest(lambda: ag.components(members, edges, masses, liquid))
    whole = fastest(lambda: ag.agglomerates())
    history = AgglomerateHistory('/tmp/viscbridge-agglomerate-cost.csv')
    row = fastest(history.record)
    step = step_time()
    a = ag.agglomerates()
    print('%7d spheres %7d bridges: agglomerates() %.3f s (reading O %.3f s, components %.3f s), a history row %.3f s; '
          'one step %.3f s → a call every 200 steps adds %.1f %%; %d agglomerates, largest %d'
          % (len(members), len(edges), whole, read, components, row, step, 100 * whole / (200 * step), a.count, a.largest))


if __name__ == '__main__':
    sys.stdout.reconfigure(line_buffering=True)
    for n in [int(a) for a in sys.argv[1:]] or [10000, 100000]:
        measure(n)
