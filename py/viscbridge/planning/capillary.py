"""The capillary force of a liquid bridge (physics.md §8; Capillary.hpp): Lian's rupture distance
(P11), the pull of Willett (P19) or Rabinovich (P20) at a gap, its stiffness $|dF/dS|$ (P22) and the
largest stiffness the time step takes.  Plain Python, the same formulas as the C++ kernels.
"""
import math

from .._checks import choice, in_range, non_negative
from .inputs import CAPILLARY_MODELS

__all__ = ['rupture_distance', 'capillary_force', 'capillary_stiffness', 'capillary_max_stiffness']


def rupture_distance(bridge_volume, contact_angle=0.0):
    """P11 (Lian et al. 1993): S_rup = (1 + θ/2) V^(1/3)."""
    bridge_volume = non_negative('rupture_distance', 'bridge_volume', bridge_volume, ' [m³]')
    contact_angle = in_range('rupture_distance', 'contact_angle', contact_angle, 0, math.pi / 2, unit=' [rad]')
    return (1.0 + 0.5 * contact_angle) * bridge_volume ** (1.0 / 3.0)


def _willett(R, surface_tension, contact_angle, bridge_volume):
    """(force, stiffness) of the gap for Willett's pull (P19), Derjaguin radius R."""
    f0, k = 2 * math.pi * R * surface_tension * math.cos(contact_angle), 0.5 * math.sqrt(R / bridge_volume)

    def force(S):
        x = k * S if S > 0 else 0.0
        return f0 / (1 + 2.1 * x + 10 * x * x)

    def stiffness(S):
        if S <= 0:
            return 0.0
        x = k * S
        d = 1 + 2.1 * x + 10 * x * x
        return f0 * k * (2.1 + 20 * x) / (d * d)
    return force, stiffness


def _rabinovich(R, surface_tension, contact_angle, bridge_volume):
    """(force, stiffness) of the gap for Rabinovich's pull (P20), Derjaguin radius R."""
    scale, theta, c = 2 * math.pi * R * surface_tension, contact_angle, 2 * bridge_volume / (math.pi * R)

    def immersion(S):
        if S <= 0:
            return 0.5 * math.sqrt(c)
        x = c / (S * S)
        return 0.5 * S * x / (math.sqrt(1 + x) + 1)

    def force(S):
        alpha = math.sqrt(2 * immersion(S) / R)
        first = -math.expm1(-0.5 * math.log1p(c / (S * S))) if S > 0 else 1.0
        return scale * (math.cos(theta) * first + math.sin(alpha) * math.sin(theta + alpha))

    def stiffness(S):
        if S <= 0:
            return 0.0
        alpha = math.sqrt(2 * immersion(S) / R)
        x = c / (S * S)
        root = math.sqrt(1 + x)
        d_first = -x / (root * (1 + x) * S)
        d_immersion = 0.5 * x / (root + 1) - 0.5 * x / root
        return abs(scale * (math.cos(theta) * d_first + math.sin(theta + 2 * alpha) * d_immersion / (R * alpha)))
    return force, stiffness


#: The (force, stiffness) makers of the capillary models that pull ('none' has neither).
_PULLS = {'willett': _willett, 'rabinovich': _rabinovich}


def _capillary(model, r_bar, surface_tension, contact_angle, bridge_volume):
    """(force, stiffness) functions of the gap for a capillary model (physics.md §8), with the
    Derjaguin radius R = 2 r̄; the same formulas as core/models/capillary/Capillary.hpp."""
    choice('capillary_force', 'model', model, CAPILLARY_MODELS)
    if model in _PULLS:
        return _PULLS[model](2 * r_bar, surface_tension, contact_angle, bridge_volume)
    return (lambda S: 0.0), (lambda S: 0.0)


def capillary_force(model, r_bar, surface_tension, contact_angle, bridge_volume, gap):
    """The capillary pull [N] at gap S (P19 'willett', P20 'rabinovich'; held at its contact value
    in overlap).  r̄ is the reduced radius (a sphere's radius against a wall)."""
    return _capillary(model, r_bar, surface_tension, contact_angle, bridge_volume)[0](gap)


def capillary_stiffness(model, r_bar, surface_tension, contact_angle, bridge_volume, gap):
    """$|dF/dS|$ of the capillary pull at gap S (P22; 0 in overlap) [N/m]."""
    return _capillary(model, r_bar, surface_tension, contact_angle, bridge_volume)[1](gap)


def capillary_max_stiffness(model, r_bar, surface_tension, contact_angle, bridge_volume, s_rup):
    """The largest $|dF/dS|$ over 0 < S ≤ S_rup (P22), as the time step takes it: Willett's in closed
    form (at s⁺ with 600 s⁺² + 126 s⁺ − 11.18 = 0), Rabinovich's sampled (log-uniform, +5 %)."""
    force, stiffness = _capillary(model, r_bar, surface_tension, contact_angle, bridge_volume)
    if model == 'willett':
        s = (-126 + math.sqrt(126.0 ** 2 + 4 * 600 * 11.18)) / 1200
        return stiffness(s / (0.5 * math.sqrt(2 * r_bar / bridge_volume)))
    if model == 'rabinovich':
        best = stiffness(0.0)
        for k in range(49):
            best = max(best, stiffness(s_rup * 10.0 ** (-6.0 * (1 - k / 48.0))))
        return 1.05 * best
    return 0.0
