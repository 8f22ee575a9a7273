"""Both schemes against the closed forms of physics.md §5 (R1–R4) at Δt ≤ 0.01 t_v: the explicit
one (the paper's framework) and the implicit one (backward Euler over the network, P15).

Errors are measured in units of the initial speed (≤ 0.5 %)."""
import math

import pytest
from yade import O, utils
from yade.wrapper import Facet

import viscbridge
from wetpairs import (R, RHO, Recorder, crossing, decay_time_pair, decay_time_wall, gap_and_approach,
                      head_on_pair, material, sphere_mass)

pytestmark = pytest.mark.slow  # closed forms at dt <= 0.01 t_v: long runs

RBAR = R / 2  # equal spheres


def pitois_G(s, a2):
    """R2: G(s) = ln s + ½ ln(s² + a²) − 2 ln(s + √(s² + a²))."""
    return math.log(s) + 0.5 * math.log(s * s + a2) - 2 * math.log(s + math.sqrt(s * s + a2))


def approach_until(s_stop, **kw):
    """Run a head-on approach, recording (S, w) after each step until S < s_stop."""
    rec = Recorder(gap_and_approach)
    while not rec.rows or rec.rows[-1][0] > s_stop:
        O.run(200, True)
        assert O.interactions.has(0, 1), 'the bridge vanished during the approach'
    return [s for s, _ in rec.rows], [w for _, w in rec.rows]


SCHEMES = pytest.mark.parametrize('integration', ['explicit', 'implicit'])


@SCHEMES
def test_R1_adams_perchard_approach(integration):
    mu, w0, S0, s_min = 1e-3, 0.1, 0.1 * R, 1e-4 * R
    head_on_pair(S0, w0, viscosity=mu, sMin=s_min, normalModel='adamsPerchard', tangentialModel='none',
                 integration=integration)
    t_v = decay_time_pair(mu, s_min)
    O.dt = 0.01 * t_v
    A = 1.8 * mu
    S, w = approach_until(0.5 * s_min)
    expected = w0 - A * math.log(S0 / s_min)
    assert expected == pytest.approx(0.087566, abs=1e-6)  # physics.md R1 example
    measured = crossing(S, w, s_min)
    assert abs(measured - expected) <= 0.005 * w0, (measured, expected)
    # below S_min the coefficient is constant: w falls linearly, w = w(S_min) − (S_min − S)/t_v
    at_half = crossing(S, w, 0.5 * s_min)
    assert abs(at_half - (expected - 0.5 * s_min / t_v)) <= 0.005 * w0


@SCHEMES
def test_R2_pitois_approach(integration):
    mu, w0, S0, s_min = 1.0, 15.0, 0.1 * R, 1e-4 * R
    volume = 0.01 * 4.0 / 3.0 * math.pi * R ** 3
    head_on_pair(S0, w0, viscosity=mu, sMin=s_min, bridgeVolume=volume, normalModel='pitois', tangentialModel='none',
                 integration=integration)
    O.dt = 0.01 * decay_time_pair(mu, s_min)
    A = 1.8 * mu
    a2 = volume / (math.pi * RBAR)
    expected = w0 - A * (pitois_G(S0, a2) - pitois_G(s_min, a2))
    assert expected == pytest.approx(4.3631, abs=2e-4)  # physics.md R2 example
    S, w = approach_until(s_min)
    measured = crossing(S, w, s_min)
    assert abs(measured - expected) <= 0.005 * w0, (measured, expected)


def bridged():
    return O.interactions.has(0, 1) and O.interactions[0, 1].isReal


def separation_run(u0, steps_max, mu=1.0, integration='explicit'):
    s_min = 1e-4 * R
    volume = 0.01 * 4.0 / 3.0 * math.pi * R ** 3
    head_on_pair(s_min, -u0, viscosity=mu, sMin=s_min, bridgeVolume=volume, tangentialModel='none',
                 formationDistance=2 * s_min, integration=integration)
    # What limits accuracy here is the relative gap change per step at S_min, u0·Δt/S_min: 0.11 at
    # Δt = 0.01 t_v for u0 = 20 m/s (a first-order error of ≈ A·0.11/2 = 0.1 m/s), hence Δt = 0.005 t_v.
    O.dt = 0.005 * decay_time_pair(mu, s_min)
    rec = Recorder(lambda: gap_and_approach() + (bridged(),))
    O.run(1, True)  # the collider creates the interaction in the first step
    assert O.interactions[0, 1].phys.bridge
    while O.iter < steps_max and bridged():
        O.run(500, True)
    return rec.rows, s_min


@SCHEMES
def test_R3_separation_escapes_with_predicted_speed(integration):
    u0, A = 20.0, 1.8
    S_rup = 0.347 * R
    assert A * math.log(S_rup / (1e-4 * R)) == pytest.approx(14.67, abs=0.01)  # escape speed
    rows, s_min = separation_run(u0, 200000, integration=integration)
    assert not bridged(), 'the bridge should have ruptured'
    S = [r[0] for r in rows if r[2]]
    u = [-r[1] for r in rows if r[2]]
    s_rup = (1 + 0) * (0.01 * 4.0 / 3.0 * math.pi * R ** 3) ** (1 / 3)
    assert s_rup == pytest.approx(S_rup, rel=2e-3)
    assert max(S) <= s_rup + u[-1] * O.dt * 2  # ruptured in the step it crossed S_rup
    expected = u0 - A * math.log(s_rup / s_min)
    assert expected == pytest.approx(5.325, abs=2e-3)  # physics.md R3 example
    assert abs(u[-1] - expected) <= 0.005 * u0, (u[-1], expected)


@SCHEMES
def test_R3_below_escape_speed_the_bridge_holds(integration):
    u0 = 14.0  # below the 14.67 m/s escape speed
    rows, s_min = separation_run(u0, 120000, integration=integration)
    assert bridged() and O.interactions[0, 1].phys.bridge
    S_star = s_min * math.exp(u0 / 1.8)  # where u(S) = 0
    assert max(r[0] for r in rows) < S_star < 0.347 * R


@pytest.mark.parametrize('support', ['wall', 'facet'])
def test_R4_settling_through_the_film(support):
    """Sphere settling onto a wall through the film, quasi-static: S = S0 exp(−t/τ_g)."""
    mu, g = 0.1, 9.81
    S0, S1 = 1e-2 * R, 1e-3 * R
    mat = material()
    if support == 'wall':
        O.bodies.append(utils.wall(0, axis=2, material=mat))
    else:
        L = 20 * R
        O.bodies.append(utils.facet([(-L, -L, 0), (L, -L, 0), (0, L, 0)], material=mat))
    O.bodies.append(utils.sphere((0, 0, R + S0), R, material=mat))
    O.engines = viscbridge.engines(gravity=(0, 0, -g), timeStepper=False, guard=False, viscosity=mu,
                                   sMin=0.5 * S1, tangentialModel='none', formationDistance=2 * S0)
    m = sphere_mass()
    tau_g = 6 * math.pi * mu * R ** 2 / (m * g)
    O.dt = 0.25 * decay_time_wall(mu, 0.5 * S1)
    ball = O.bodies[1].state

    def gap():  # the wall and the facet both lie in the plane z = 0
        return ball.pos[2] - R

    samples = []
    O.run(1, True)
    assert O.interactions[0, 1].phys.bridge  # formed at S0, before contact
    while not samples or samples[-1][1] > S1:
        O.run(2000, True)
        samples.append((O.time, gap(), -ball.vel[2]))
    assert O.interactions[0, 1].phys.bridge
    # log S is linear in t on the quasi-static path: interpolate the crossing time in log S
    t = crossing([math.log(s) for _, s, _ in samples], [t for t, _, _ in samples], math.log(S1))
    w = crossing([math.log(s) for _, s, _ in samples], [w for _, _, w in samples], math.log(S1))
    t_expected = tau_g * math.log(S0 / S1)
    assert t_expected == pytest.approx(0.08450, rel=1e-3)  # physics.md R4 example
    assert t == pytest.approx(t_expected, rel=0.005)
    assert w == pytest.approx(S1 / tau_g, rel=0.005)
    assert S1 / tau_g == pytest.approx(1.3625e-5, rel=1e-3)
    # the identity m w − m g t − 6πμ r² ln S = const holds for S > S_min (with inertia)
    first, last = samples[0], samples[-1]
    inv = [m * w - m * g * t - 6 * math.pi * mu * R ** 2 * math.log(s) for t, s, w in (first, last)]
    assert abs(inv[1] - inv[0]) <= 0.005 * 6 * math.pi * mu * R ** 2 * math.log(S0 / S1)
