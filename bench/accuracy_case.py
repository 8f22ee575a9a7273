"""The cases of the accuracy benchmarks (bench/accuracy_cost.py, bench/accuracy_target.py): a scene
followed for a time T and sampled every T/10, run at a fixed Δt or with the time stepper, and the
error measures of docs/performance.md §1 against a reference run.

Cases:
  Bed45       a bed of 45 spheres (r = 0.5 mm, 2500 kg/m³, E = 10 MPa) settled dry in a narrow walled
              column, then wetted (every contact a bridge, Adams–Perchard + slip, S_min = 1e-3 r̄)
              and given random velocities of up to 1 cm/s; T = 1e-4 s.  The critical-Δt scans' trial.
  Settling300 viscbridge.scenes.settling(n=300) with random initial speeds of 5 cm/s (bridges form in
              the cloud as spheres meet) and the same liquid; T = 2e-3 s.
  pair        a head-on pair whose bridge stiffens 100-fold as it stops (R1), not tuned on;
  pair_implicit  the same with the tolerance given to integration='implicit'.
  wall        a 5 mm sphere thrown at 3 m/s onto a wall through a bridge: viscous approach, Hertz
              impact, capture; gravity on; T = 3e-4 s (the approach and the impact); not tuned on.
  capillary   a pair at rest pulled into contact by its bridge's capillary force against the viscous
              one, then settling in contact; T = 4e-2 s; not tuned on.

Error measures, each relative to a reference run:
  e_x  RMS over the spheres of |x(T) - x_ref(T)|, divided by the RMS displacement of the reference
       over the run.
  e_K  the integral over the run of |K(t) - K_ref(t)|, divided by the integral of K_ref: K recorded at
       every step of both runs, the run's interpolated geometrically between its steps (a decay is
       geometric) onto the reference's steps.
  e_K_sampled  the sum over the sample times of |K - K_ref|, divided by the sum of K_ref: a ten-point
       quadrature of e_K that misses what happens between the samples (the wall impact's kinetic
       energy falls 160-fold before the first), kept in the tables for comparison.
  error = max(e_x, e_K).
A run with the time stepper does not land on the sample times: it stops at the first step at or
after each (O.stopAtTime), and the reference is carried to that instant with its slopes (dK/dt, and
the velocities for the positions), a second-order correction.
"""
import math
import os
import random

import common
from yade import O, utils
import yade.wrapper as yw

import viscbridge
import viscbridge.scan as scan
from viscbridge.measures import capillary_input
from viscbridge.scenes import instability

R = 0.5e-3
SAMPLES = 10
LIQUID = dict(sMinRel=1e-3, normalModel='adamsPerchard', tangentialModel='slip')


class Bed45:
    name = 'bed45'
    T = 1e-4
    PERTURBATION = 0.01

    def __init__(self):
        self.bed = scan.settled_bed(os.path.join(common.CACHE, 'narrow-bed-45.yade.gz'), n=45, radius=R, width=6 * R, seed=5)

    def prepare(self, mu, integration, stepper=False, safety=None, accuracy=None):
        O.load(self.bed)
        O.interactions.clear()
        O.engines = viscbridge.engines(viscosity=mu, integration=integration, timeStepper=stepper, safety=safety,
                                       guard=False, minRadius=R, accuracy=accuracy, **LIQUID)
        rng = random.Random(6)
        for b in O.bodies:
            if b.dynamic:
                b.state.vel = tuple(rng.uniform(-self.PERTURBATION, self.PERTURBATION) for _ in range(3))
        O.trackEnergy = False


class Settling300:
    name = 'settling300'
    T = 2e-3

    def prepare(self, mu, integration, stepper=False, safety=None, accuracy=None):
        from viscbridge.scenes import settling
        # a fixed dt here only selects the scene without the stepper: run_fixed sets the step
        settling(n=300, viscosity=mu, initialSpeed=0.05, integration=integration, dt=None if stepper else 1.0,
                 safety=safety, accuracy=accuracy, guard=False, trackEnergy=False, **LIQUID)


class StiffeningPair:
    """Two spheres approaching head-on through a bridge whose viscous coefficient grows 100-fold as the gap
    closes (Adams–Perchard, C ∝ 1/S): physics.md R1, w(S) = w0 − A ln(S0/S) with A = 1.8 μ, stopping at
    S0/100.  Not tuned on: the estimate's cases were the beds.  The speed scales with μ, so every
    viscosity is the same run in other units."""
    name = 'pair'
    S0 = 0.1 * R
    GROWTH = 100.0

    def __init__(self):
        self.T = None

    def speed(self, mu):
        return 1.8 * mu * math.log(self.GROWTH)

    def prepare(self, mu, integration, stepper=False, safety=None, accuracy=None):
        A, w0 = 1.8 * mu, self.speed(mu)
        self.T = self.S0 / w0 + 30 * (self.S0 / self.GROWTH) / A  # the approach, then 30 relaxation times
        O.reset()
        mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
        O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((2 * R + self.S0, 0, 0), R, material=mat)])
        O.bodies[0].state.vel, O.bodies[1].state.vel = (0.5 * w0, 0, 0), (-0.5 * w0, 0, 0)
        O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=mu, integration=integration, timeStepper=stepper, safety=safety,
                                       guard=False, minRadius=R, accuracy=accuracy, sMin=1e-4 * R, normalModel='adamsPerchard',
                                       tangentialModel='none', formationDistance=1.5 * self.S0)
        O.trackEnergy = False


class StiffeningPairImplicit(StiffeningPair):
    """The stiffening pair with the tolerance given to the implicit scheme (integration='implicit')
    instead of letting the stepper choose."""
    name = 'pair_implicit'
    integration = 'implicit'


class WallImpact:
    """A sphere of r = 5 mm thrown at 3 m/s onto a wall, with gravity, through a bridge that forms
    0.1 r above it: the bridge takes most of the speed (Adams–Perchard, 1000-fold stiffening to
    S_min = 1e-4 r), the rest goes into a Hertz impact (E = 10 MPa, about 1 ms), and the bridge holds
    the sphere on the rebound.  Not tuned on.  The speed does not scale with μ: from 10 Pa·s the
    bridge stops the sphere before it touches."""
    name = 'wall'
    RADIUS = 5e-3
    SPEED = 3.0
    T = 3e-4

    def prepare(self, mu, integration, stepper=False, safety=None, accuracy=None):
        O.reset()
        r, S0 = self.RADIUS, 0.1 * self.RADIUS
        mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
        O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, r + 0.9 * S0), r, material=mat)])
        O.bodies[1].state.vel = (0, 0, -self.SPEED)
        O.engines = viscbridge.engines(viscosity=mu, integration=integration, timeStepper=stepper, safety=safety, guard=False,
                                       minRadius=r, accuracy=accuracy, sMin=1e-4 * r, normalModel='adamsPerchard',
                                       tangentialModel='slip', formationDistance=S0)
        O.trackEnergy = False


class CapillaryPair:
    """Two spheres (r = 0.5 mm) at rest 0.02 r apart, pulled together by their bridge's capillary force
    (Willett, γ = 0.07 N/m, θ = 0, 1 % of a sphere's volume) against its viscous resistance: the gap
    closes about exponentially (C ∝ 1/S against an almost constant pull), then the pair settles in
    Hertz contact held by the pull.  No gravity.  Not tuned on; a conservative force the estimate
    has not met."""
    name = 'capillary'
    S0 = 0.02 * R
    T = 4e-2

    def prepare(self, mu, integration, stepper=False, safety=None, accuracy=None):
        O.reset()
        mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
        O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((2 * R + self.S0, 0, 0), R, material=mat)])
        O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=mu, integration=integration, timeStepper=stepper, safety=safety,
                                       guard=False, minRadius=R, accuracy=accuracy, sMin=1e-4 * R, normalModel='adamsPerchard',
                                       tangentialModel='slip', formationDistance=1.5 * self.S0, capillaryModel='willett',
                                       surfaceTension=0.07, contactAngle=0.0, bridgeVolumeRel=0.01)
        O.trackEnergy = False


CASES = {c.name: c for c in (Bed45, Settling300, StiffeningPair, StiffeningPairImplicit, WallImpact, CapillaryPair)}


def _dynamic():
    return [b.id for b in O.bodies if b.dynamic]


def _start_timing():
    O.timingEnabled = True
    for e in O.engines:
        e.execTime, e.execCount = 0, 0


TRACE = []  # (time, kinetic energy) after every step of the run in progress


def _trace():
    TRACE.append((O.time, utils.kineticEnergy()))


def _engine_seconds():
    seconds = sum(e.execTime for e in O.engines if not isinstance(e, yw.PyRunner)) * 1e-9
    O.timingEnabled = False
    return seconds


def _sampled(case, advance, slopes=False):
    """Advance the prepared scene through the SAMPLES sample times: advance(t) runs up to time t.
    Returns the record of the run (see run_fixed)."""
    dyn = _dynamic()
    x0 = {i: O.bodies[i].state.pos for i in dyn}
    z0 = {i: O.bodies[i].state.pos[2] for i in dyn}
    ke0, iter0, t0 = utils.kineticEnergy(), O.iter, O.time
    TRACE[:] = [(t0, ke0)]
    O.engines = O.engines + [yw.PyRunner(iterPeriod=1, command='import accuracy_case; accuracy_case._trace()')]
    _start_timing()
    times, kinetic, slope, why = [], [], [], None
    for j in range(1, SAMPLES + 1):
        k_before = advance(t0 + j * case.T / SAMPLES, slopes)
        ke = utils.kineticEnergy()
        released = sum(O.bodies[i].state.mass * 9.81 * (z0[i] - O.bodies[i].state.pos[2]) for i in dyn) + capillary_input()
        why = instability(ke, released, ke0)
        if why:
            break
        times.append(O.time - t0)
        kinetic.append(ke)
        if slopes:
            slope.append((ke - k_before) / O.dt)
    seconds = _engine_seconds()
    O.engines = O.engines[:-1]
    solver = next((e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver)), None)
    stepper = next((e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper)), None)
    return dict(times=times, kinetic=kinetic, slopes=slope, x0=x0, seconds=seconds, steps=O.iter - iter0, why=why,
                trace=[(t - t0, k) for t, k in TRACE], pos={i: O.bodies[i].state.pos for i in dyn}, vel={i: O.bodies[i].state.vel for i in dyn},
                cg=solver.totalIterations / max(solver.solves, 1) if solver else None,
                estimate=stepper.errorEstimate if stepper else None,
                switches=stepper.schemeSwitches if stepper else None)


def run_fixed(case, mu, integration, k, tolerance=None, slopes=False):
    """Run T at Δt = T/SAMPLES/k (the implicit solver at `tolerance`, else its default).  With
    `slopes`, also dK/dt at each sample (the reference of runs that do not land on the samples)."""
    case.prepare(mu, integration)
    O.dt = case.T / SAMPLES / k
    if tolerance is not None:
        next(e for e in O.engines if isinstance(e, yw.ViscBridgeImplicitSolver)).tolerance = tolerance

    def advance(t, slopes):
        O.run(k - 1 if slopes else k, True)
        before = utils.kineticEnergy() if slopes else None
        if slopes:
            O.run(1, True)
        return before
    return _sampled(case, advance, slopes)


def run_stepper(case, mu, integration=None, safety=None, accuracy=None, max_dt=None):
    """Run T with ViscBridgeTimeStepper (at `safety`, with the tolerance `accuracy`, integration
    'auto' by default when it is given; Δt held at most `max_dt`, its maxDt), stopping at the first
    step at or after each sample time."""
    integration = integration or (getattr(case, 'integration', None) if accuracy else None)
    case.prepare(mu, integration, stepper=True, safety=safety, accuracy=accuracy)
    if max_dt:
        next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper)).maxDt = max_dt
    O.dt = 0  # the stepper's first step sets it from its bound, without the growth limit

    def advance(t, slopes):
        O.stopAtTime = t
        O.run()
        O.wait()
    return _sampled(case, advance)


def kinetic_error(r, ref):
    """e_K: ∫|K − K_ref| dt / ∫K_ref dt over the reference's steps, the run's K interpolated
    geometrically between its own steps (linearly where it is zero)."""
    import numpy as np
    t, k = np.array(r['trace']).T
    tr, kr = np.array(ref['trace']).T
    tr, kr = tr[tr <= t[-1]], kr[tr <= t[-1]]
    positive = np.all(k > 0)
    run = np.exp(np.interp(tr, t, np.log(k))) if positive else np.interp(tr, t, k)
    return np.trapezoid(np.abs(run - kr), tr) / np.trapezoid(kr, tr)


def errors(r, ref, sampled=False):
    """(e_x, e_K) of run r against ref (e_K_sampled with `sampled`: the reference carried to r's
    sample instants by its slopes)."""
    if r['why'] or len(r['kinetic']) < SAMPLES:
        return math.inf, math.inf
    ids = list(ref['pos'])
    shift = r['times'][-1] - ref['times'][-1]
    rms = lambda vs: math.sqrt(sum(v.squaredNorm() for v in vs) / len(vs))  # noqa: E731
    at_end = {i: ref['pos'][i] + shift * ref['vel'][i] for i in ids}
    e_x = rms([r['pos'][i] - at_end[i] for i in ids]) / rms([ref['pos'][i] - ref['x0'][i] for i in ids])
    k_ref = [k + (t - tr) * s for k, s, t, tr in zip(ref['kinetic'], ref['slopes'] or [0] * SAMPLES, r['times'], ref['times'])]
    e_k = sum(abs(a - b) for a, b in zip(r['kinetic'], k_ref)) / sum(ref['kinetic'])
    return e_x, (e_k if sampled else kinetic_error(r, ref))
