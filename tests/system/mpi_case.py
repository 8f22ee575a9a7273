"""The settling scene of tests/system/test_mpi.py, run serially (`yade -n -x mpi_case.py OUT ...`) or
split by yade.mpy (`mpiexec -n N yade -n -x mpi_case.py OUT ...`).

Every rank writes OUT.rank<k>.json: its own dt at every step, the error that stopped it (if any)
and, on rank 0 (which holds the merged scene at the end), the positions, O.energy summed over the
ranks, the initial kinetic energy and the bridges.  Options (after OUT):
  --integration explicit|implicit   --steps N   --viscosity MU   --speed V (initial, m/s)   --tolerance TOL (implicit)
  --dt DT         a fixed time step (no ViscBridgeTimeStepper)
  --rayleigh-fraction F   ViscBridgeTimeStepper.rayleighFraction (1: the contacts, not the Rayleigh bound, set dt)
  --no-guard      without ViscBridgeGuard
  --mismatch      run 5 steps, then give rank 1 twice the dt and run on (must be refused)
  --no-decompose  leave every particle to the master (must be refused)
  --clump         add a clump of two wet spheres to worker 1 (must be refused: mpy has no clumps)
  --film  liquidModel='film' (every sphere's film 1 % of its volume)
  --fixed-sphere  a fixed wettable sphere, left to the master (with --film: must be refused)
  --moving-wall engine|velocity   a wall moved by a TranslationEngine, or with its velocity set (the
                  ViscBridgeBoundaryMotion decompose() adds moves it on the workers)
  --no-boundary-motion  without that engine (a moving wall must then be refused: mpy moves the
                  master's bodies on the master only)
  --measure-split run without merging, then call the scene's measures on every rank: agglomerates
                  (a collective: the whole scene's, recorded, and rank 0's of the merged scene after
                  mp.mergeScene()); the liquid's totals and distribution and the VTK particles (collectives; a piece per rank)
  --history       an AgglomerateHistory recorder every 50 steps (OUT.agglomerates.csv, written by rank 0;
                  its rows recorded on every rank)
  --events        the test engine ViscBridgeEventCounter after the interaction loop (its counts per rank)
  --save FILE     rank 0 saves the merged scene at the end
  --load FILE     serially: load FILE (saved by --save), try a step (refused), viscbridge.mpi.to_serial(), run
"""
import argparse
import json
import os
import sys

from yade import O, utils
import yade.wrapper as yw

import viscbridge.mpi
import viscbridge.scenes as scenes

ap = argparse.ArgumentParser()
ap.add_argument('out')
ap.add_argument('--integration', default='explicit')
ap.add_argument('--steps', type=int, default=300)
ap.add_argument('--viscosity', type=float, default=0.01)
ap.add_argument('--speed', type=float, default=0.3)
ap.add_argument('--tolerance', type=float, default=None)
ap.add_argument('--dt', type=float, default=None)
ap.add_argument('--rayleigh-fraction', type=float, default=None)
ap.add_argument('--accuracy', type=float, default=None)
ap.add_argument('--film', action='store_true', help="liquidModel='film', every sphere's film 1 % of its volume")
ap.add_argument('--fixed-sphere', action='store_true', help='add a fixed (wettable) sphere, which decompose() leaves to the master')
ap.add_argument('--no-guard', action='store_true')
ap.add_argument('--mismatch', action='store_true')
ap.add_argument('--no-decompose', action='store_true')
ap.add_argument('--clump', action='store_true')
ap.add_argument('--moving-wall', choices=('engine', 'velocity'), default=None)
ap.add_argument('--no-boundary-motion', action='store_true')
ap.add_argument('--events', action='store_true')
ap.add_argument('--history', action='store_true')
ap.add_argument('--measure-split', action='store_true')
ap.add_argument('--save', default=None)
ap.add_argument('--load', default=None)
args = ap.parse_args(sys.argv[1:])

distributed = 'OMPI_COMM_WORLD_SIZE' in os.environ  # serial runs do not even import mpy
if distributed:
    from yade import mpy as mp
    mp.VERBOSE_OUTPUT = False


def build():
    """40 spheres in a column 5 diameters wide, thrown at 0.3 m/s (--speed) into each other and the walls,
    bridges forming within 0.5 r: many bridges (across the subdomains too) and a large part of the
    energy dissipated within 300 steps."""
    film = dict(liquidModel='film', filmRel=0.01) if args.film else {}
    scenes.settling(n=40, viscosity=args.viscosity, seed=3, initialSpeed=args.speed, cloudFraction=0.25, formationDistance=2.5e-4, width=5e-3,
                    integration=args.integration, dt=args.dt, guard=not args.no_guard, **film)
    if args.tolerance:
        for e in O.engines:
            if isinstance(e, yw.ViscBridgeImplicitSolver):
                e.tolerance = args.tolerance
    for e in O.engines:
        if isinstance(e, yw.ViscBridgeTimeStepper):
            if args.rayleigh_fraction:
                e.rayleighFraction = args.rayleigh_fraction
            if args.accuracy:
                e.accuracy = args.accuracy
    if args.fixed_sphere:
        top = max(b.state.pos[2] for b in O.bodies if isinstance(b.shape, yw.Sphere)) + 1e-3
        O.bodies.append(utils.sphere((1e-3, 1e-3, top), 2e-4, fixed=True, material=O.bodies[-1].material))
    if args.events:
        loop = next(i for i, e in enumerate(O.engines) if isinstance(e, yw.InteractionLoop))
        O.engines = O.engines[:loop + 1] + [yw.ViscBridgeEventCounter(label='eventCounter')] + O.engines[loop + 1:]
    if not args.no_decompose:
        viscbridge.mpi.decompose(axis=0)
    if args.no_boundary_motion:
        O.engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeBoundaryMotion)]
    if args.clump:
        mat = O.bodies[-1].material
        top = max(b.state.pos[2] for b in O.bodies if isinstance(b.shape, yw.Sphere)) + 1e-3
        O.bodies.appendClumped([utils.sphere((1e-3, 1e-3, top), 2e-4, material=mat), utils.sphere((1.4e-3, 1e-3, top), 2e-4, material=mat)])
        for b in O.bodies:
            if b.isClump or b.isClumpMember:
                b.subdomain = 1
    if args.moving_wall:
        wall = next(b for b in O.bodies if not b.dynamic)
        if args.moving_wall == 'engine':
            newton = next(i for i, e in enumerate(O.engines) if isinstance(e, yw.NewtonIntegrator))
            O.engines = O.engines[:newton] + [yw.TranslationEngine(ids=[wall.id], translationAxis=(0, 0, 1), velocity=1e-3)] + O.engines[newton:]
        else:
            wall.state.vel = (0, 0, 1e-3)
    O.engines = O.engines + [yw.PyRunner(iterPeriod=1, initRun=True, command='DTS.append(O.dt)', label='dtRecorder')]
    if args.history:
        from viscbridge.analysis.agglomerate_history import AgglomerateHistory
        global HISTORY
        HISTORY = AgglomerateHistory(args.out + '.agglomerates.csv')
        O.engines = O.engines + [HISTORY.recorder(iterPeriod=50)]


if args.load:
    O.load(args.load)
else:
    build()
initial_kinetic = utils.kineticEnergy()
DTS = []
import builtins
builtins.DTS = DTS  # PyRunner commands run in __main__ of yade, not here

me = viscbridge.mpi.rank()
result = dict(rank=me, ranks=viscbridge.mpi.ranks(), error=None)
if args.film:
    import viscbridge.liquid as liquid
    result['initialLiquid'] = liquid.total()  # every rank holds the whole scene until the split


def agglomerate_record(a):
    return dict(ids=[int(i) for i in a.ids], labels=[int(k) for k in a.labels], sizes=[int(s) for s in a.sizes],
                coordination=a.coordination)


def run(steps):
    if distributed:
        mp.mpirun(steps, mp.numThreads, withMerge=True)
    else:
        O.run(steps, True)


if args.load:  # a merged scene runs on serially only once it is made serial again
    try:
        O.run(1, True)
    except RuntimeError as error:
        result['refusedBeforeToSerial'] = str(error)
    result['toSerial'] = viscbridge.mpi.to_serial()
guards = [e for e in O.engines if isinstance(e, yw.ViscBridgeGuard)]
error_before = guards[0].lastError if guards else ''
try:
    if args.measure_split:
        mp.mpirun(args.steps, mp.numThreads, withMerge=False)
        import viscbridge.liquid as liquid
        import viscbridge.vtk as vtk
        split = viscbridge.agglomerates()
        result['splitAgglomerates'] = agglomerate_record(split)
        spread = liquid.distribution()  # collectives: the whole scene's on every rank
        result['splitLiquid'] = [liquid.total(), liquid.in_bridges(), spread.ids.tolist(), spread.liquid.tolist()]
        result['vtkPiece'] = [vtk.write_particles(args.out + '.vtp'), os.path.exists(vtk.piece_path(args.out + '.vtp', me))]
        mp.mergeScene()  # so that every rank ends together
        if me == 0:
            result['mergedAgglomerates'] = agglomerate_record(viscbridge.agglomerates())
            spread = liquid.distribution()
            result['mergedLiquid'] = [liquid.total(), liquid.in_bridges(), spread.ids.tolist(), spread.liquid.tolist()]
    elif args.mismatch:
        run(5)
        if me == 1:
            O.dt *= 2
        run(args.steps)
    else:
        run(args.steps)
except Exception as error:  # every rank must stop with the same message, none may hang
    result['error'] = '%s: %s' % (type(error).__name__, error)
if result['error'] is None and guards and guards[0].lastError != error_before:
    # YADE's O.run(n, True) can miss an error thrown in the engine thread at the very first step
    # (it returns as if the run had finished, O.iter still 0): the guard has kept the message
    result['error'] = 'RuntimeError: ' + guards[0].lastError
result['iter'] = O.iter
counters = [e for e in O.engines if isinstance(e, yw.ViscBridgeEventCounter)]
if counters:
    c = counters[0]
    result['events'] = dict(formed=c.formed, ruptured=c.ruptured, mismatches=c.mismatches, outOfOrder=c.outOfOrder)
result['dts'] = DTS
if args.history:
    result['historyRows'] = [[r['iter'], r['agglomerates'], r['largest'], r['coordination']] for r in HISTORY.rows]
    if me == 0:
        with open(args.out + '.agglomerates.csv') as fh:
            result['historyCsvLines'] = sum(1 for line in fh if line.strip())
liquids = [e for e in O.engines if isinstance(e, yw.ViscBridgeLiquid)]
if liquids and result['error'] is None:  # each rank counts the bridges it accounts for
    result['filmEvents'] = [sum(c) for c in zip(*viscbridge.mpi.allgather((liquids[0].formed, liquids[0].ruptured)))]
if result['error'] is None:
    result['energy'] = viscbridge.mpi.energy()
    if me == 0:
        spheres = [b for b in O.bodies if isinstance(b.shape, yw.Sphere)]
        if liquids:
            result['films'] = {b.id: b.state.film for b in spheres}
            result['liquid'] = [liquid.in_films(), liquid.in_bridges()]
        result['positions'] = {b.id: list(b.state.pos) for b in spheres}
        bridges = [i for i in O.interactions if i.isReal and i.phys.bridge]
        result['bridges'] = len(bridges)
        result['crossBridges'] = sum(1 for i in bridges if min(O.bodies[i.id1].subdomain, O.bodies[i.id2].subdomain) > 0
                                     and O.bodies[i.id1].subdomain != O.bodies[i.id2].subdomain)
        result['initialKinetic'] = initial_kinetic
        solver = [e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver)]
        if solver:
            result['solver'] = dict(iterations=solver[0].totalIterations, solves=solver[0].solves, residual=solver[0].residual,
                                    tolerance=solver[0].tolerance)
        guard = [e for e in O.engines if isinstance(e, yw.ViscBridgeGuard)]
        if guard:
            result['guardChecks'] = guard[0].checks
if args.save and me == 0 and result['error'] is None:
    O.save(args.save)
with open('%s.rank%d.json' % (args.out, me), 'w') as fh:
    json.dump(result, fh)
