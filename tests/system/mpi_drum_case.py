"""The product's drum (viscbridge.scenes.drum: facets a RotationEngine turns, 'fixed' liquid) run
serially (`yade -n -x mpi_drum_case.py OUT ...`) or split by yade.mpy (`mpiexec -n N yade -n -x
mpi_drum_case.py OUT ...`), for tests/system/test_mpi_drum.py.

Every rank writes OUT.rank<k>.json: the error that stopped it (if any), O.iter, and its own copy of
some facets' position and orientation (the workers' copies must follow the master's); rank 0, which
holds the merged scene at the end, also the spheres' positions and velocities, O.energy summed over
the ranks and the guard's checks.  Options (after OUT):
  --steps N   --integration explicit|implicit   --tolerance TOL (implicit)
  --no-boundary-motion  without the ViscBridgeBoundaryMotion decompose() adds (must be refused)
"""
import argparse
import json
import os
import sys

from yade import O
import yade.wrapper as yw

import viscbridge.mpi
import viscbridge.scenes as scenes

ap = argparse.ArgumentParser()
ap.add_argument('out')
ap.add_argument('--steps', type=int, default=1500)
ap.add_argument('--integration', default='implicit')
ap.add_argument('--tolerance', type=float, default=None)
ap.add_argument('--no-boundary-motion', action='store_true')
args = ap.parse_args(sys.argv[1:])

distributed = viscbridge.mpi.ranks() > 1
if distributed:
    from yade import mpy as mp
    mp.VERBOSE_OUTPUT = False

r = 1e-3
drum = scenes.drum(radius=r, drumRadius=12 * r, n=150, froude=0.3, liquidModel='fixed', integration=args.integration)
if args.tolerance:
    next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver)).tolerance = args.tolerance
viscbridge.mpi.decompose(axis=0)
if args.no_boundary_motion:
    O.engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeBoundaryMotion)]

me = viscbridge.mpi.rank()
result = dict(rank=me, ranks=viscbridge.mpi.ranks(), error=None)
try:
    if distributed:
        mp.mpirun(args.steps, mp.numThreads, withMerge=True)
    else:
        O.run(args.steps, True)
except Exception as error:  # every rank must stop with the same message, none may hang
    result['error'] = '%s: %s' % (type(error).__name__, error)
result['iter'] = O.iter
# mpy erases on a worker the master's bodies that do not reach its subdomain: the facets it holds
result['facets'] = {i: list(O.bodies[i].state.pos) + list(O.bodies[i].state.ori) for i in drum.facets if O.bodies[i] is not None}
if result['error'] is None:
    result['energy'] = viscbridge.mpi.energy()
    if me == 0:
        spheres = [O.bodies[i] for i in drum.spheres]
        result['positions'] = [list(b.state.pos) for b in spheres]
        result['velocities'] = [list(b.state.vel) for b in spheres]
        result['time'] = O.time
        result['guardChecks'] = next(e.checks for e in O.engines if isinstance(e, yw.ViscBridgeGuard))
        result['bridges'] = sum(1 for i in O.interactions if i.isReal and i.phys.bridge)
with open('%s.rank%d.json' % (args.out, me), 'w') as fh:
    json.dump(result, fh)
