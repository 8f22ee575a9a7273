"""Shared set-up of the ViscBridge benchmarks: settled beds, engine lists, timing in the same process.

Step times come from YADE's own per-engine timers (O.timingEnabled, nanoseconds, no Python in the
loop); configurations are measured in interleaved rounds so that machine drift hits them alike.
"""
import json
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
CACHE = os.path.join(HERE, '.cache')
RESULTS = os.path.join(os.path.dirname(HERE), 'docs', 'perf')


#: The configurations of the law-cost benchmarks, see engines().
CONFIGS = ['yade_mindlin', 'vb_dry', 'vb_normal_adamsPerchard', 'vb_normal_pitois', 'vb_tangential_slip',
           'vb_tangential_goldman', 'vb_tangential_washino', 'vb_contact_damping', 'vb_capillary_willett',
           'vb_capillary_rabinovich', 'vb_all', 'vb_all_film', 'yade_implicit_lubrication']


def bed(n, seed=5):
    """A bed of n spheres (r = 0.5 mm) settled dry in a walled column (cached)."""
    import viscbridge.scan as scan
    return scan.dry_bed(scan.normalize_case(dict(n=n, seed=seed)), CACHE)


def lattice(nx, ny, nz, radius=0.5e-3, **engine_options):
    """A lattice of nx × ny × nz touching spheres (0.01 % overlap) on a floor, every neighbour contact
    a bridge of Adams–Perchard + slip, with viscbridge.engines(**engine_options); O.dt = 1e-9."""
    from yade import O, utils
    import yade.wrapper as yw
    import viscbridge
    O.reset()
    mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
    pitch = 2 * radius * (1 - 1e-4)
    O.bodies.append(utils.wall(0, axis=2, sense=1, material=mat))
    O.bodies.append([utils.sphere((i * pitch, j * pitch, radius * (1 - 1e-4) + k * pitch), radius, material=mat)
                     for i in range(nx) for j in range(ny) for k in range(nz)])
    O.engines = viscbridge.engines(normalModel='adamsPerchard', tangentialModel='slip', **engine_options)
    O.dt = 1e-9


def engines(config):
    """The engine list of a named configuration; every one has the same collider, geometry
    functors and integrator, only the physics and the law differ."""
    import yade.wrapper as yw
    loop_geoms = [yw.Ig2_Sphere_Sphere_ScGeom(), yw.Ig2_Wall_Sphere_ScGeom()]
    ip2, law = None, None
    vb = dict(
        vb_dry=dict(viscosity=0.0),
        vb_normal_adamsPerchard=dict(viscosity=1.0, normalModel='adamsPerchard', tangentialModel='none'),
        vb_normal_pitois=dict(viscosity=1.0, normalModel='pitois', tangentialModel='none'),
        vb_tangential_slip=dict(viscosity=1.0, normalModel='none', tangentialModel='slip'),
        vb_tangential_goldman=dict(viscosity=1.0, normalModel='none', tangentialModel='goldman'),
        vb_tangential_washino=dict(viscosity=1.0, normalModel='none', tangentialModel='washino'),
        vb_contact_damping=dict(viscosity=0.0, en=0.5),
        vb_capillary_willett=dict(viscosity=0.0, capillaryModel='willett', surfaceTension=0.072),
        vb_capillary_rabinovich=dict(viscosity=0.0, capillaryModel='rabinovich', surfaceTension=0.072),
        vb_all=dict(viscosity=1.0, normalModel='adamsPerchard', tangentialModel='slip', en=0.5),
        # the same with conserved liquid: bridges take it from films (set in load()), ViscBridgeLiquid after the loop
        vb_all_film=dict(viscosity=1.0, normalModel='adamsPerchard', tangentialModel='slip', en=0.5, liquidModel='film'),
    )
    if config == 'yade_mindlin':
        ip2, law = yw.Ip2_FrictMat_FrictMat_MindlinPhys(), yw.Law2_ScGeom_MindlinPhys_Mindlin()
    elif config == 'yade_implicit_lubrication':
        # YADE's implicit lubrication: 6D sphere geometry, and interactions that exist before
        # contact (it refuses to start from an overlap; see load())
        loop_geoms[0] = yw.Ig2_Sphere_Sphere_ScGeom6D(interactionDetectionFactor=1.05)
        # a sphere reaching a wall needs its interaction before contact too (YADE's own wall
        # functor creates it at contact, which that law rejects): ViscBridge's wall functor with the
        # same 5 % range — geometry only, the physics and law stay YADE's
        loop_geoms[1] = yw.Ig2_Wall_Sphere_ViscBridgeScGeom(detectionDistance=0.05 * 0.5e-3)
        ip2 = yw.Ip2_FrictMat_FrictMat_LubricationPhys(eta=1.0, eps=1e-3)
        law = yw.Law2_ScGeom_ImplicitLubricationPhys(resolution=2)
        return [yw.ForceResetter(), yw.InsertionSortCollider([yw.Bo1_Sphere_Aabb(aabbEnlargeFactor=1.05), yw.Bo1_Wall_Aabb()]),
                yw.InteractionLoop(loop_geoms, [ip2], [law]), yw.NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.0)]
    elif config in vb:
        ip2 = yw.Ip2_FrictMat_FrictMat_ViscBridgePhys(**vb[config])
        law = yw.Law2_ScGeom_ViscBridgePhys_HertzViscous()
    else:
        raise ValueError('unknown configuration %r' % config)
    # as viscbridge.engines() builds it: the law's forces summed per body after the loop, then the films
    after = ([yw.ViscBridgeForceSum()] if config in vb else []) + ([yw.ViscBridgeLiquid()] if getattr(ip2, 'liquidModel', None) == 'film' else [])
    return [yw.ForceResetter(), yw.InsertionSortCollider([yw.Bo1_Sphere_Aabb(), yw.Bo1_Wall_Aabb()]),
            yw.InteractionLoop(loop_geoms, [ip2], [law])] + after + [yw.NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.0)]


def load(bed_path, config, dt=1e-9):
    """The bed with the configuration's engines; every contact re-created by its physics."""
    from yade import O
    import yade.wrapper as yw
    O.load(bed_path)
    if config == 'yade_implicit_lubrication':
        # Law2_ScGeom_ImplicitLubricationPhys cannot start from the bed's Hertz overlaps (up to a
        # few per mille of r, more at the bottom of a tall bed): shrink every sphere by the largest
        # relative overlap plus 0.2 % (at least 1 %) so that every contact starts as a small gap
        overlap = max([i.geom.penetrationDepth / min(O.bodies[k].shape.radius for k in (i.id1, i.id2)
                                                     if isinstance(O.bodies[k].shape, yw.Sphere))
                       for i in O.interactions if i.isReal and i.geom.penetrationDepth > 0] + [0.0])
        shrink = max(0.01, overlap + 0.002)
        for b in O.bodies:
            if isinstance(b.shape, yw.Sphere):
                b.shape.radius *= 1 - shrink
    O.interactions.clear()
    O.engines = engines(config)
    if config.endswith('_film'):  # every sphere wetted with 5 % of its volume
        import viscbridge.liquid
        spheres = [b.id for b in O.bodies if isinstance(b.shape, yw.Sphere)]
        viscbridge.liquid.set_film(spheres, [0.05 * 4 / 3 * 3.141592653589793 * O.bodies[i].shape.radius ** 3 for i in spheres])
    O.dt = dt
    O.trackEnergy = False


def random_velocities(speed=0.01, seed=3):
    """Give every dynamic body a random velocity of up to `speed` per component, so that the implicit
    solver has work at every step."""
    import random
    from yade import O
    rng = random.Random(seed)
    for b in O.bodies:
        if b.dynamic:
            b.state.vel = tuple(rng.uniform(-speed, speed) for _ in range(3))


# ViscBridgeImplicitSolver's wall-time counters [s], one per part of its step (the solve's products and
# preconditioner are parts of timeSolve).
SOLVER_TIMES = ('timeGather', 'timeFactorise', 'timeSolve', 'timeProducts', 'timePreconditioner', 'timeApply', 'timeEnergy', 'timeEstimate')


def engine_seconds_per_step(steps):
    """Run `steps` steps and return the summed engine time per step [s] (YADE's timers)."""
    from yade import O
    O.timingEnabled = True
    for e in O.engines:
        e.execTime, e.execCount = 0, 0
    O.run(steps, True)
    total = sum(e.execTime for e in O.engines)
    O.timingEnabled = False
    return total * 1e-9 / steps


def interleaved(configs, measure, rounds=7):
    """measure(config) for every config, `rounds` times interleaved; the minimum per config.

    On the shared virtual machines this runs on, timings of identical runs scatter by up to 50 %
    upwards (other tenants); the minimum is the run least disturbed, and interleaving exposes every
    configuration to the same drift.  bench/law_cost_instructions.py counts instructions instead."""
    samples = {c: [] for c in configs}
    for _ in range(rounds):
        for c in configs:
            samples[c].append(measure(c))
    return {c: min((x for x in v if not math.isnan(x)), default=math.nan) for c, v in samples.items()}, samples


def run_on_ranks(script, args, ranks):
    """The result of a benchmark's worker: `script` run as ``yade -n -j1 -x SCRIPT ARGS... OUT`` in a
    fresh directory, serially (`ranks` 1) or under mpiexec on `ranks` MPI ranks, one thread each; it
    writes its result as JSON to OUT, the last argument (rank 0's, under MPI)."""
    import subprocess
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, 'result.json')
        yade = ['yade', '-n', '-j1', '-x', script, *[str(a) for a in args], out]
        mpi = ['mpiexec', '--allow-run-as-root', '--oversubscribe', '-n', str(ranks)] if ranks > 1 else []
        # a private TMPDIR: mpiexec names its session directory after its PID, which repeats in yadew's PID namespaces
        subprocess.run(mpi + yade, check=True, cwd=tmp, env=dict(os.environ, OMP_NUM_THREADS='1', TMPDIR=tmp),
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        with open(out) as fh:
            return json.load(fh)


def rows_with_earlier(path, rows, key):
    """The rows of the CSV at `path` whose key(row) none of `rows` has, then `rows`: a run of some
    configurations keeps the others' earlier results.  key(row) must give the same for a row read
    back from the CSV (text) as for the row that was written (numbers)."""
    import csv
    if not os.path.exists(path):
        return list(rows)
    measured = {key(r) for r in rows}
    with open(path) as fh:
        earlier = [{k: v for k, v in r.items() if v != ''} for r in csv.DictReader(fh)]
    return [r for r in earlier if key(r) not in measured] + list(rows)


def write_rows(path, rows):
    import csv
    os.makedirs(os.path.dirname(path), exist_ok=True)
    keys = list(dict.fromkeys(k for r in rows for k in r))  # every row's columns, in the order met (older rows lack newer ones)
    with open(path, 'w', newline='') as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    return path
