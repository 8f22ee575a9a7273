"""ViscBridgeTimeStepper (physics.md §3): its viscous bound is exact for an equal pair, and at the
default safety a wet packing stays stable and free of spurious rebound at every viscosity."""
import math
import random

import pytest
from yade import O
from yade.wrapper import PyRunner, ViscBridgeTimeStepper

import viscbridge.scenes as scenes
from wetpairs import R, decay_time_pair, gap_and_approach, head_on_pair

RBAR = R / 2
S_MIN = 1e-3 * RBAR


def stepper():
    return next(e for e in O.engines if isinstance(e, ViscBridgeTimeStepper))


def test_viscous_bound_of_an_equal_pair_is_two_decay_times():
    head_on_pair(0.5 * S_MIN, 1e-15, viscosity=1.0, sMin=S_MIN, tangentialModel='none')
    O.engines = O.engines[:3] + [ViscBridgeTimeStepper(safety=1.0)] + O.engines[3:]
    O.dt = 1e-12
    O.run(1, True)
    ts = stepper()
    assert ts.dtViscous == pytest.approx(2 * decay_time_pair(1.0, S_MIN), rel=0.01)
    assert ts.governing == 'viscous-network'
    assert ts.criticalBody in (0, 1)


@pytest.mark.parametrize('factor,grows', [(1.05, True), (0.95, False)])
def test_pair_run_around_the_stepper_bound(factor, grows):
    """The explicit pair run at the stepper's dtViscous (safety 1) × 1.05 grows, × 0.95 decays."""
    head_on_pair(0.5 * S_MIN, 1e-15, viscosity=1.0, sMin=S_MIN, tangentialModel='none')
    O.engines = O.engines[:3] + [ViscBridgeTimeStepper(safety=1.0)] + O.engines[3:]
    O.dt = 1e-12
    O.run(1, True)
    bound = stepper().dtViscous
    stepper().active = False
    O.dt = factor * bound
    w0 = abs(gap_and_approach()[1])
    O.run(60, True)
    assert (abs(gap_and_approach()[1]) > w0) == grows


# --- wet packings -------------------------------------------------------------------------------
@pytest.fixture(scope='module')
def dry_bed(tmp_path_factory):
    """300 spheres settled dry on the floor of the walled column, saved to a file."""
    O.reset()
    bed = scenes.settling(n=300, viscosity=0.0, dt=None, seed=5, trackEnergy=False, guard=False)
    bed.run(duration=0.08)
    path = str(tmp_path_factory.mktemp('bed') / 'bed.yade.gz')
    O.save(path)
    return path


def wet(path, mu, seed=9):
    """The dry bed made wet: every contact becomes a bridge at S_min (the stiffest viscous state),
    the particles get random velocities of 1 cm/s, and the stepper picks dt (default safety)."""
    O.load(path)
    O.interactions.clear()  # new interactions get ViscBridgePhys with the liquid below
    ip2 = O.engines[2].physDispatcher.functors[0]
    ip2.viscosity = mu
    rng = random.Random(seed)
    for b in O.bodies:
        if b.dynamic:
            b.state.vel = tuple(rng.uniform(-0.01, 0.01) for _ in range(3))
    O.trackEnergy = False


class AlternationCounter:
    """Counts interactions whose relative normal velocity changes sign in two consecutive steps
    (+ − + or − + −) and keeps at least a tenth of its size at each change: the period-2 oscillation
    that a dashpot shows when Δt exceeds its decay time (spurious rebound: the velocity is multiplied
    by 1 − Δt/t_v < −0.1 each step).  At the default safety the top mode sits at the no-rebound
    limit itself (Δt/t_v = 1 within the estimate's 1e-3), where a sign flip of a thousandth of the
    velocity, gone the next step, is not a rebound.  Sampled on windows of three steps."""

    def __init__(self, window_every):
        self.history, self.count, self.samples = {}, 0, 0
        self.every = window_every
        O.engines = O.engines + [PyRunner(iterPeriod=1, command='import test_time_stepper as t; t.COUNTER.sample()')]
        global COUNTER
        COUNTER = self

    def sample(self):
        phase = O.iter % self.every
        if phase > 2:
            return
        if phase == 0:
            self.history = {}
        for i in O.interactions:
            if not i.isReal or not i.phys.bridge:
                continue
            b1, b2 = O.bodies[i.id1].state, O.bodies[i.id2].state
            vn = (b1.vel - b2.vel).dot(i.geom.normal)
            self.history.setdefault((i.id1, i.id2), []).append(vn)
        if phase == 2:
            self.samples += 1
            scale = max((abs(v) for vs in self.history.values() for v in vs), default=0.0)
            for vs in self.history.values():
                if (len(vs) == 3 and min(abs(v) for v in vs) > 1e-6 * scale and vs[0] * vs[1] < 0 and vs[1] * vs[2] < 0
                        and abs(vs[1]) >= REBOUND * abs(vs[0]) and abs(vs[2]) >= REBOUND * abs(vs[1])):
                    self.count += 1


COUNTER = None  # the active counter, for its PyRunner
REBOUND = 0.1  # the smallest ratio of consecutive reversed velocities counted as a rebound


def released_and_kinetic(z0):
    from yade import utils
    released = sum(O.bodies[i].state.mass * 9.81 * (z - O.bodies[i].state.pos[2]) for i, z in z0.items())
    return utils.kineticEnergy(), released


@pytest.mark.parametrize('mu', [1e-3, 1.0, 100.0, 1000.0])
def test_default_safety_keeps_wet_packings_stable_without_rebound(dry_bed, mu):
    wet(dry_bed, mu)
    z0 = {b.id: b.state.pos[2] for b in O.bodies if b.dynamic}
    ke0 = released_and_kinetic(z0)[0]
    counter = AlternationCounter(window_every=50)
    worst = 0.0
    for _ in range(15):
        O.run(100, True)
        ke, released = released_and_kinetic(z0)
        assert math.isfinite(ke) and ke <= ke0 + max(released, 0.0), (ke, ke0, released)
        worst = max(worst, ke)
    bridges = sum(1 for i in O.interactions if i.isReal and i.phys.bridge)
    assert bridges > 300  # a wet packing: the test is not vacuous
    assert stepper().governing in (('rayleigh', 'collision') if mu < 0.01 else ('viscous-network',))
    assert counter.samples >= 25
    if mu >= 1.0:
        # Viscosity-dominated (overdamped) contacts cannot oscillate: a velocity that flips sign at
        # consecutive steps is the numerical rebound off S_min.  At μ = 1e-3 the contacts are
        # elastic and bounce for real, so only the energy bound applies there.
        assert counter.count == 0, '%d period-2 oscillations (spurious rebounds) at μ = %g' % (counter.count, mu)


@pytest.mark.parametrize('mu', [1.0, 1000.0])
def test_first_step_after_wetting_a_loaded_bed_is_within_the_limit(dry_bed, mu):
    """The stepper saved with the dry bed resumes its state only for the network it was computed on:
    wetted after loading (interactions re-created as bridges), the bed's first step is already
    within the wet limit and puts no energy in.  (It once took the dry step there, 120 times the
    limit at 1 Pa·s, and the kinetic energy jumped 2000-fold before the next step corrected dt.)"""
    wet(dry_bed, mu)
    z0 = {b.id: b.state.pos[2] for b in O.bodies if b.dynamic}
    ke0 = released_and_kinetic(z0)[0]
    O.run(1, True)
    assert sum(1 for i in O.interactions if i.isReal and i.phys.bridge) > 300
    ke, released = released_and_kinetic(z0)
    assert ke <= ke0 + max(released, 0.0)
    first = O.dt
    stepper().reset()  # a fresh estimate of the wet network, to compare with
    O.run(1, True)
    ts = stepper()
    assert first <= ts.dtNetwork / ts.safety  # within the stability limit (dtNetwork/safety is below it)
    assert first <= 1.02 * ts.dtRitz  # and at the safety asked, within the estimates' scatter (0.6 % seen)


def test_rebound_check_detects_a_too_large_step(dry_bed):
    """Negative control: at Δt = 1.5 t_v of the stiffest bridge (stable for a pair, but beyond its
    no-rebound limit t_v) the same packing oscillates."""
    wet(dry_bed, 100.0)
    O.run(1, True)
    stepper().active = False
    t_v = min(i.phys.mEff / i.phys.cn for i in O.interactions if i.isReal and i.phys.bridge and i.phys.cn > 0)
    O.dt = 1.5 * t_v
    counter = AlternationCounter(window_every=10)
    O.run(60, True)
    assert counter.count > 0
