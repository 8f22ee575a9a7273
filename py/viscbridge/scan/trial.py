"""One case, inside YADE: the trial — a dry bed (:mod:`.beds`) wetted, every contact a bridge at
S_min, released with small random velocities and run at a fixed Δt — and the bisection of the
case's critical Δt (:func:`find_critical_dt`).  The measures and the instability criterion are those
of :mod:`viscbridge.measures`.
"""
import math
import time

from ..measures import (capillary_input, energy_released, instability, kinetic_energy, period_two_ringing,
                        scene_gravity)
from .beds import dry_bed
from .bisection import bisect_threshold
from .cases import _LIQUID_KEYS, case_key, normalize_case
from .._yade_run import run_steps, run_until

__all__ = ['find_critical_dt']


class _Trial:
    """A wetted bed run at a fixed Δt; see the package docstring."""

    def __init__(self, case, bed):
        self.case, self.bed = case, bed

    def prepare(self):
        """Load the bed, re-create every contact as a bridge of the case's liquid, set the case's
        integration and random velocities, and note where the released energy counts from."""
        import random
        from yade import O
        import yade.wrapper as yw
        O.load(self.bed)
        O.interactions.clear()  # every contact is re-created as a bridge with this liquid
        loop = next(e for e in O.engines if isinstance(e, yw.InteractionLoop))
        ip2 = loop.physDispatcher.functors[0]
        for k in _LIQUID_KEYS:
            setattr(ip2, k, self.case[k])
        loop.lawDispatcher.functors[0].integration = self.case['integration']
        engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeImplicitSolver)]
        if self.case['integration'] == 'implicit':  # the solver goes right before the integrator
            at = next(k for k, e in enumerate(engines) if isinstance(e, yw.NewtonIntegrator))
            engines.insert(at, yw.ViscBridgeImplicitSolver())
        O.engines = engines
        rng = random.Random(self.case['seed'] + 1)
        v = self.case['perturbation']
        for b in O.bodies:
            if b.dynamic:
                b.state.vel = tuple(rng.uniform(-v, v) for _ in range(3))
        self.z0 = {b.id: b.state.pos[2] for b in O.bodies if b.dynamic}
        self.gravity = scene_gravity()  # the bed's own, as scenes.settling set it
        self.ke0 = kinetic_energy()
        self.capillary0 = capillary_input()

    def measures(self):
        """Kinetic energy, and the energy released since prepare(): potential energy and the
        capillary forces' input."""
        return kinetic_energy(), energy_released(self.z0, self.gravity, self.capillary0)

    def unstable_at(self, dt):
        """Run `steps` steps at dt; the instability criterion's reason, or None."""
        from yade import O
        import yade.wrapper as yw
        self.prepare()
        O.engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeTimeStepper)]
        O.dt = dt
        checks = 40
        for _ in range(checks):
            run_steps(max(1, self.case['steps'] // checks))
            ke, released = self.measures()
            why = instability(ke, released, self.ke0)
            if why:
                return why
        return period_two_ringing() if self.case['verdict'] == 'period2' else None

    def stepper_dt(self):
        """The time stepper's Δt (default safety) on the wetted bed, with its bounds."""
        from yade import O
        import yade.wrapper as yw
        self.prepare()
        ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
        run_steps(1)  # interactions are created and the stepper runs once
        run_steps(60)  # dt may only grow by maxGrowth per step: let it settle
        contacts = [i for i in O.interactions if i.isReal]
        dyn = sum(1 for b in O.bodies if b.dynamic)
        return dict(dt_stepper=O.dt, dt_stepper_collision=ts.dtCollision, dt_stepper_viscous=ts.dtViscous,
                    governing=ts.governing, bridges=sum(1 for i in contacts if i.phys.bridge),
                    coordination=2.0 * len(contacts) / max(dyn, 1))


    def accuracy_run(self, duration):
        """Run `duration` [s] of the trial with the tolerance case['accuracy'] (physics.md §7a): the
        stepper chooses Δt and the scheme.  Its cost and estimated error, and whether it stayed stable."""
        from yade import O
        import yade.wrapper as yw
        self.prepare()
        engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeImplicitSolver)]
        at = next(k for k, e in enumerate(engines) if isinstance(e, yw.NewtonIntegrator))
        engines.insert(at, yw.ViscBridgeImplicitSolver())
        O.engines = engines
        ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
        ts.accuracy, ts.autoIntegration = self.case['accuracy'], True
        ts.resetErrorEstimate()  # the account of this run, not of the bed's settling
        O.dt, iter0 = 0, O.iter  # the stepper's first step starts from its bound (A4)
        O.timingEnabled = True
        for e in O.engines:
            e.execTime = 0
        run_until(O.time + duration)
        seconds = sum(e.execTime for e in O.engines) * 1e-9
        O.timingEnabled = False
        ke, released = self.measures()
        return dict(accuracy_steps=O.iter - iter0, accuracy_seconds=seconds, accuracy_error_estimate=ts.errorEstimate,
                    accuracy_switches=ts.schemeSwitches, accuracy_scheme=ts.scheme,
                    accuracy_unstable=instability(ke, released, self.ke0) or '')


def find_critical_dt(case, cache_dir):
    """Bisection of the critical Δt of one case (runs inside YADE).  Returns a result dict."""
    from .. import criteria
    case = normalize_case(case)
    started = time.time()
    trial = _Trial(case, dry_bed(case, cache_dir))
    info = trial.stepper_dt()
    r_small = case['radius'] * (1 - (case['sizeRatio'] - 1) / (case['sizeRatio'] + 1))
    s_min = case['sMinRel'] * r_small / 2
    t_v = criteria.viscous_decay_time(r_small, case['density'], case['viscosity'], s_min) if case['viscosity'] > 0 else math.inf
    rayleigh = criteria.rayleigh_dt(r_small, case['density'], case['young'], case['poisson'])
    guess = info['dt_stepper']
    lo, hi, trials = bisect_threshold(lambda dt: trial.unstable_at(dt), guess, 4 * guess, case['tolerance'])
    critical = math.sqrt(lo * hi)
    result = dict(case, key=case_key(case), dt_critical=critical, dt_stable=lo, dt_unstable=hi,
                  t_v=t_v, rayleigh_dt=rayleigh, trials=len(trials), wall_seconds=time.time() - started, **info)
    result['critical_over_tv'] = critical / t_v if math.isfinite(t_v) else None
    result['critical_over_stepper'] = critical / info['dt_stepper']
    if case['accuracy'] > 0:  # the same simulated time as a trial at the largest stable Δt
        result.update(trial.accuracy_run(case['steps'] * lo))
    return result
