"""The product's drum (viscbridge.scenes.drum: facets a RotationEngine turns, 'fixed' liquid) run
serially (`yade -n -x mpi_drum_case.py OUT ...`) or split by yade.mpy (`mpiexec -n N yade -n -x
mpi_drum_case.py OUT ...`), for tests/system/test_mpi_drum.py.

Every rank writes OUT.rank<k>.json: the error that stopped it (if any), O.iter, and its own copy of
some facets' position and orientation (the workers' copies must follow the master's); rank 0, which
holds the merged scene at the end, also the spheres' positions and velocities, O.energy summed over
the ranks and the guard's checks.  Options (after OUT):
  --steps N   --integration explicit|implicit   --tolerance TOL (implicit)
  --no-boundary-motion  without the ViscBridgeBoundaryMotion decompose() adds (must be refused)
  --n SPHERES (150; above, a drum of 16 mm)  --save FILE (rank 0, the merged scene after the run)  --load FILE: serially, the saved scene made
  serial (viscbridge.mpi.to_serial()) and run --steps more, its liquid before and after
  --migrate N: N steps split, then mpy.migrateBodies moves 3 spheres from rank 1 to rank 2, then on
  --vtk N: a bridge_recorder (bridges, particles, boundary) every N steps, its last frame summed up
  by rank 0 in the result  --liquid fixed|film  --wet-fraction F (film)  --reallocate N (mpy's REALLOCATE_FREQUENCY)  --history N: an AgglomerateHistory every N steps
  (OUT.csv, written by rank 0) and the liquid's total and CoV, measured on every rank at the same
  steps by a PyRunner (collectives while the scene is split)
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
ap.add_argument('--n', type=int, default=150)
ap.add_argument('--liquid', default='fixed')
ap.add_argument('--wet-fraction', type=float, default=0.15)
ap.add_argument('--history', type=int, default=0)
ap.add_argument('--vtk', type=int, default=0, help='a viscbridge.vtk.bridge_recorder every N steps')
ap.add_argument('--save', default=None, help='rank 0 saves the merged scene there after the run')
ap.add_argument('--load', default=None, help='serially: load a saved scene, viscbridge.mpi.to_serial(), run --steps more')
ap.add_argument('--migrate', type=int, default=0, help='N steps split, 3 spheres moved from rank 1 to 2 (mpy.migrateBodies), then on')
ap.add_argument('--reallocate', type=int, default=0, help="mpy's REALLOCATE_FREQUENCY")
args = ap.parse_args(sys.argv[1:])

distributed = viscbridge.mpi.ranks() > 1
if distributed:
    from yade import mpy as mp
    mp.VERBOSE_OUTPUT = False
    mp.REALLOCATE_FREQUENCY = args.reallocate

if args.load:
    import viscbridge.liquid as liquid
    O.load(args.load)
    O.engines = [e for e in O.engines if not isinstance(e, yw.PyRunner)]  # the saving script's measures and recorders
    viscbridge.mpi.to_serial()
    liquids = [liquid.total()]
    O.run(args.steps, True)
    liquids.append(liquid.total())
    engine = next(e for e in O.engines if isinstance(e, yw.ViscBridgeLiquid))
    with open('%s.rank0.json' % args.out, 'w') as fh:
        json.dump(dict(error=None, iter=O.iter, liquid=liquids, formed=engine.formed, ruptured=engine.ruptured), fh)
    sys.exit(0)

r = 1e-3
film = {'wetFraction': args.wet_fraction} if args.liquid == 'film' else {}
drum = scenes.drum(radius=r, drumRadius=(12 if args.n <= 150 else 16) * r, n=args.n, froude=0.3, liquidModel=args.liquid, integration=args.integration, **film)
if args.tolerance:
    next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver)).tolerance = args.tolerance
viscbridge.mpi.decompose(axis=0)
if args.no_boundary_motion:
    O.engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeBoundaryMotion)]

assigned = {i: O.bodies[i].subdomain for i in drum.spheres} if distributed else {}
if args.vtk:
    import viscbridge.vtk
    O.engines = O.engines + [viscbridge.vtk.bridge_recorder(args.out + '-', iterPeriod=args.vtk)]
me = viscbridge.mpi.rank()
result = dict(rank=me, ranks=viscbridge.mpi.ranks(), error=None, liquid=[])
if args.history:
    from viscbridge.analysis.agglomerate_history import AgglomerateHistory
    import viscbridge.liquid as liquid
    history = AgglomerateHistory(args.out + '.csv', drum=drum)
    result['initialLiquid'] = liquid.total()


    def measure_liquid():
        spread = liquid.distribution()
        # bridges this rank holds between two workers' spheres (each held by both): 0 serially
        between = lambda i: 0 < O.bodies[i.id1].subdomain != O.bodies[i.id2].subdomain > 0
        across = sum(1 for i in O.interactions if i.isReal and i.phys.bridge and between(i)) if distributed else 0
        # a worker's copies of its neighbours' spheres ("mirrors") must carry their owners' films
        held = {b.id: getattr(b.state, 'film', 0.0) for b in O.bodies if b is not None and isinstance(b.shape, yw.Sphere)}
        films = {}
        for part in viscbridge.mpi.allgather(held if me > 0 else {}):  # the master's copies are not kept up to date
            for i, v in part.items():
                films.setdefault(i, set()).add(v)
        stale = sum(1 for values in films.values() if len(values) > 1)
        result['liquid'].append([O.iter, liquid.total(), liquid.in_films(), spread.cov, len(spread.ids), across, stale])


    O.engines = O.engines + [history.recorder(iterPeriod=args.history),
                             yw.PyRunner(command='measure_liquid()', iterPeriod=args.history)]
try:
    if distributed and args.migrate:
        mp.mpirun(args.migrate, mp.numThreads, withMerge=False)
        moved = sorted(b.id for b in O.bodies if b is not None and b.subdomain == 1)[:3] if me == 1 else []
        mp.migrateBodies(moved, 1, 2)
        if me == 1:
            O.subD.completeSendBodies()
        mp.mpirun(args.steps - args.migrate, mp.numThreads, withMerge=True)
    elif distributed:
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
        result['reassigned'] = sum(1 for i, d in assigned.items() if O.bodies[i].subdomain != d)  # by mpy's reallocation
        result['films'] = [getattr(b.state, 'film', 0.0) for b in spheres]
        result['bridgeVolumes'] = sorted([i.id1, i.id2, i.phys.bridgeVolume] for i in O.interactions if i.isReal and i.phys.bridge)
        if args.history:
            result['finalLiquid'] = liquid.total()
            result['history'] = history.rows


def last_vtk_frame():
    """Of each kind, the last frame of the collection as ParaView reads it: its pieces and their data
    arrays joined (the files of a split frame hold each body and interaction once)."""
    import xml.etree.ElementTree as ET
    frame = {}
    for kind in ('bridges', 'particles', 'boundary'):
        entries = list(ET.parse('%s-%s.pvd' % (args.out, kind)).getroot().iter('DataSet'))
        last = [e for e in entries if e.get('timestep') == entries[-1].get('timestep')]
        arrays = {}
        for e in last:
            for a in ET.parse(os.path.join(os.path.dirname(args.out), e.get('file'))).getroot().iter('DataArray'):
                arrays.setdefault(a.get('Name'), []).extend(float(x) for x in (a.text or '').split())
        frame[kind] = dict(pieces=[e.get('part') for e in last], frames=len({e.get('timestep') for e in entries}), arrays=arrays)
    return frame


if args.save and me == 0 and result['error'] is None:
    O.save(args.save)
if args.vtk and me == 0 and result['error'] is None:
    result['vtk'] = last_vtk_frame()
with open('%s.rank%d.json' % (args.out, me), 'w') as fh:
    json.dump(result, fh)
