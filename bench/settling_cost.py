# A 0.1 s settling run: the implicit scheme at the collision (Hertz) step against the explicit
# scheme at its critical step, and YADE's own Law2_ScGeom_ImplicitLubricationPhys on the same cloud.
#
#   ./yadew run bench/settling_cost.py [MU ...]      (default: 1 100 1000 Pa·s; 3–8 min)
#
# ViscBridge implicit and YADE run in ROUNDS interleaved rounds (μ by μ, ours then YADE's) and the
# fastest run of each is kept, as everywhere in bench/ (common.interleaved explains why).
#
# The scene is viscbridge.scenes.settling(n=300): a loose cloud (solid fraction 0.2) falling onto
# the floor of a walled column, bridges forming at contact, Adams–Perchard + slip, S_min = 1e-3 r̄.
#   implicit   ViscBridgeTimeStepper (safety 0.5; governed by the collisions), run for 0.1 s; once
#              more per μ with errorFilterInterval = 1, for the every-step estimate (untimed).
#   explicit   its critical step is the one measured on the settled bed of the study
#              (docs/data/critical_dt_explicit.csv, same particles and liquid): 0.1 s at that step
#              is too long to run at 100 and 1000 Pa·s, so its wall time is projected from the
#              measured cost of 400 explicit steps on the settled state the implicit run reached.
#   YADE       Law2_ScGeom_ImplicitLubricationPhys(resolution=2), Ip2_FrictMat_FrictMat_
#              LubricationPhys(eta=μ, eps=1e-3), at the implicit run's time step, for 0.1 s;
#              interactions from 5 % of r before contact (that law rejects one created in contact;
#              for walls, ViscBridge's Ig2_Wall_Sphere_ViscBridgeScGeom provides the range).
# Wall time is measured around the whole run (time.perf_counter) and as the engines' own time.
import csv
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # yade -x: __file__ is yade's own
import common  # noqa: E402
from yade import O  # noqa: E402
import yade.wrapper as yw  # noqa: E402

import viscbridge.scenes as scenes  # noqa: E402

DURATION = 0.1
N = 300
R = 0.5e-3
viscosities = [float(a) for a in sys.argv[1:]] or [1.0, 100.0, 1000.0]
STUDY = os.path.join(os.path.dirname(common.HERE), 'docs', 'data', 'critical_dt_explicit.csv')


def critical_dt(mu):
    """The measured explicit critical Δt of the study's default case (300 spheres, r = 0.5 mm)."""
    with open(STUDY) as fh:
        for r in csv.DictReader(fh):
            if (float(r['viscosity']) == mu and float(r['sMinRel']) == 1e-3 and float(r['radius']) == R
                    and float(r['sizeRatio']) == 1.0 and r['normalModel'] == 'adamsPerchard'):
                return float(r['dt_critical'])
    raise LookupError('no measured critical dt for viscosity %g in %s' % (mu, STUDY))


def engine_seconds():
    return sum(e.execTime for e in O.engines) * 1e-9


def timed_run(duration):
    """Run `duration` seconds of simulated time; (wall seconds, engine seconds, steps)."""
    O.timingEnabled = True
    for e in O.engines:
        e.execTime, e.execCount = 0, 0
    start, iter0 = time.perf_counter(), O.iter
    O.stopAtTime = O.time + duration
    O.run(-1, True)
    O.stopAtTime = 0
    wall = time.perf_counter() - start
    O.timingEnabled = False
    return wall, engine_seconds(), O.iter - iter0


def state_summary(scene):
    ke, released = scene.kinetic_energy(), scene.released_energy()
    return ke, released, scenes.instability(ke, released, scene.initial_kinetic)


ROUNDS = 3


def implicit_run(mu, filter_interval=None):
    """ViscBridge implicit at the stepper's (collision) step for 0.1 s: the row, and the solver.
    filter_interval: the stepper's errorFilterInterval (None: its default)."""
    scene = scenes.settling(n=N, radius=R, viscosity=mu, integration='implicit', trackEnergy=False)
    stepper = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
    if filter_interval is not None:
        stepper.errorFilterInterval = filter_interval
    wall, engines_s, steps = timed_run(DURATION)
    solver = next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver))
    ke, released, why = state_summary(scene)
    row = dict(viscosity=mu, run='viscbridge implicit', dt=O.dt, steps=steps, wall_seconds=wall,
               engine_seconds=engines_s, projected=False, cg_iterations_per_step=solver.totalIterations / max(solver.solves, 1),
               factorisations=solver.factorisations, fallbacks=solver.fallbacks, bridges=scene.bridges(),
               kinetic_over_released=ke / released, unstable=why or '', error_estimate=stepper.errorEstimate,
               estimate_filters=solver.estimateFilters)
    row.update({'solver_seconds': solver.execTime * 1e-9, 'interaction_loop_seconds': engine_time(yw.InteractionLoop)})
    row.update({k: getattr(solver, k) for k in common.SOLVER_TIMES})
    return row, scene


def engine_time(kind):
    return sum(e.execTime for e in O.engines if isinstance(e, kind)) * 1e-9


def explicit_projection(mu, scene):
    """ViscBridge explicit at its critical step: the cost of 400 steps on the settled state, projected to 0.1 s."""
    # switch the law itself: existing interactions keep the law functor they were first handled by
    # (YADE caches it in Interaction.functorCache), so a new engine list would not reach them
    law = next(f for e in O.engines if isinstance(e, yw.InteractionLoop) for f in e.lawDispatcher.functors)
    law.integration = 'explicit'
    O.engines = [e for e in O.engines if not isinstance(e, (yw.ViscBridgeImplicitSolver, yw.ViscBridgeTimeStepper, yw.ViscBridgeGuard))]
    dt_crit = critical_dt(mu)
    O.dt = 0.5 * dt_crit
    O.run(20, True)
    per_step = common.engine_seconds_per_step(400)
    steps_explicit = int(math.ceil(DURATION / dt_crit))
    return dict(viscosity=mu, run='viscbridge explicit', dt=dt_crit, steps=steps_explicit,
                wall_seconds=per_step * steps_explicit, engine_seconds=per_step * steps_explicit, projected=True,
                cg_iterations_per_step=None, factorisations=None, fallbacks=None, bridges=scene.bridges(),
                kinetic_over_released=None, unstable='')


def yade_run(mu, dt):
    """YADE's implicit lubrication on the same cloud, at the same step, for 0.1 s."""
    scene = scenes.settling(n=N, radius=R, viscosity=mu, trackEnergy=False, dt=dt)
    O.engines = [yw.ForceResetter(),
                 yw.InsertionSortCollider([yw.Bo1_Sphere_Aabb(aabbEnlargeFactor=1.05), yw.Bo1_Wall_Aabb()]),
                 yw.InteractionLoop([yw.Ig2_Sphere_Sphere_ScGeom6D(interactionDetectionFactor=1.05), yw.Ig2_Wall_Sphere_ViscBridgeScGeom(detectionDistance=0.05 * R)],
                                    [yw.Ip2_FrictMat_FrictMat_LubricationPhys(eta=mu, eps=1e-3)],
                                    [yw.Law2_ScGeom_ImplicitLubricationPhys(resolution=2)]),
                 yw.NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.0)]
    wall, engines_s, steps = timed_run(DURATION)
    ke, released, why = state_summary(scene)
    return dict(viscosity=mu, run='yade ImplicitLubrication', dt=O.dt, steps=steps, wall_seconds=wall,
                engine_seconds=engines_s, projected=False, cg_iterations_per_step=None, factorisations=None,
                fallbacks=None, bridges=sum(1 for i in O.interactions if i.isReal),
                kinetic_over_released=ke / released if released > 0 else None, unstable=why or '')


best, explicit, slowest, every_step = {}, {}, {}, {}
for r in range(ROUNDS):
    for mu in viscosities:
        if mu not in every_step:  # the estimate filtered in full at every step (physics.md A1d), once
            every_step[mu] = implicit_run(mu, filter_interval=1)[0]['error_estimate']
        ours, scene = implicit_run(mu)
        if mu not in explicit:
            explicit[mu] = explicit_projection(mu, scene)
        theirs = yade_run(mu, ours['dt'])
        for row in (ours, theirs):
            key = (mu, row['run'])
            slowest[key] = max(slowest.get(key, 0.0), row['wall_seconds'])
            if key not in best or row['wall_seconds'] < best[key]['wall_seconds']:
                best[key] = row
        print('round %d μ=%-6g ours %.2f s (CG %.2f it/step), YADE %.2f s' % (
            r + 1, mu, ours['wall_seconds'], ours['cg_iterations_per_step'], theirs['wall_seconds']), flush=True)

rows = []
for mu in viscosities:
    ours, theirs = best[(mu, 'viscbridge implicit')], best[(mu, 'yade ImplicitLubrication')]
    ours['ratio_to_yade'] = ours['wall_seconds'] / theirs['wall_seconds']
    ours['estimate_over_every_step'] = ours['error_estimate'] / every_step[mu]
    for row in (ours, theirs):  # the slowest of the rounds: the scatter of this machine
        row['slowest_wall_seconds'], row['rounds'] = slowest[(mu, row['run'])], ROUNDS
    rows += [ours, explicit[mu], theirs]
rows = [{k: r.get(k) for k in dict.fromkeys(k for r in rows for k in r)} for r in rows]  # every row every column

out = common.write_rows(os.path.join(common.RESULTS, 'settling_cost_%dthreads.csv' % O.numThreads), rows)
print('\n0.1 s settling of %d spheres, %d thread(s), fastest of %d interleaved rounds' % (N, O.numThreads, ROUNDS))
print('%8s %-26s %11s %12s %12s %9s' % ('μ', 'run', 'dt [s]', 'steps', 'wall [s]', 'CG/step'))
for r in rows:
    print('%8g %-26s %11.3e %12d %12.1f%s %9s' % (r['viscosity'], r['run'], r['dt'], r['steps'], r['wall_seconds'],
                                                   '*' if r['projected'] else ' ',
                                                   '%.2f' % r['cg_iterations_per_step'] if r['cg_iterations_per_step'] is not None else '-'))
print('(* projected from the cost of 400 steps)')
for mu in viscosities:
    ours = best[(mu, 'viscbridge implicit')]
    print('μ=%g: error estimate %.3g, %.2f× the one filtered every step (%d full filters in %d steps)' % (
        mu, ours['error_estimate'], ours['estimate_over_every_step'], ours['estimate_filters'], ours['steps']))
    print('μ=%g: ViscBridge implicit / YADE ImplicitLubrication = %.2f; solver %.2f s of %.2f s (gather %.2f, refresh %.2f, '
          'solve %.2f = products %.2f + preconditioner %.2f + rest, apply %.2f, energy %.2f, error estimate %.2f), InteractionLoop %.2f s'
          % (mu, ours['ratio_to_yade'], ours['solver_seconds'], ours['wall_seconds'], ours['timeGather'], ours['timeFactorise'],
             ours['timeSolve'], ours['timeProducts'], ours['timePreconditioner'], ours['timeApply'], ours['timeEnergy'],
             ours['timeEstimate'], ours['interaction_loop_seconds']))
print('written', out)
