"""The viscous coefficients of a liquid bridge (physics.md §2; NormalViscous.hpp,
GoldmanCoefficients.hpp, TangentialViscous.hpp): the normal coefficient C^n of Adams–Perchard (P4)
or Pitois (P5), the viscous decay time t_v (P12), Goldman's tangential coefficients C_T, C_R, C_W
(P8, P9) and a bridge's largest damping as the time step sees it (P14, P14a).  Plain Python.
"""
import math

from .._checks import choice, non_negative, positive, reject
from .inputs import NORMAL_MODELS, TANGENTIAL_MODELS, _geometry
from .materials import reduced_mass, reduced_radius, sphere_mass

__all__ = ['ROT', 'pitois_volume_factor', 'normal_coefficient', 'viscous_decay_time', 'tangential_coefficients',
           'viscous_step_coefficient']

#: Ratio of a sphere's rotational to translational mobility seen at its surface: r²/I · m = 5/2.
ROT = 2.5


def pitois_volume_factor(r_bar, gap, bridge_volume):
    """Pitois' factor [1 − (1 + V/(π r̄ S²))^(−1/2)]² ∈ (0, 1] (P5), computed as the kernel does:
    −expm1(−½ log1p(x)) for the bracket, x = V/(π r̄ S²)."""
    a2 = bridge_volume / (math.pi * r_bar)
    bracket = -math.expm1(-0.5 * math.log1p(a2 / (gap * gap)))
    return bracket * bracket


def normal_coefficient(r_bar, viscosity, gap, normal_model='adamsPerchard', bridge_volume=None):
    """Normal viscous coefficient C^n at gap S (the caller passes the clamped gap max(S, S_min), P6).

    'adamsPerchard' (P4): C^n = 6πμ r̄²/S;  'pitois' (P5): C^n = 6πμ r̄²/S · [1 − (1 + V/(π r̄ S²))^(−1/2)]²;
    'none': 0.
    """
    choice('normal_coefficient', 'normal_model', normal_model, NORMAL_MODELS)
    if normal_model == 'none' or viscosity == 0:
        return 0.0
    positive('normal_coefficient', 'gap', gap, ' [m] (the clamped gap max(S, S_min))')
    c = 6 * math.pi * viscosity * r_bar * r_bar / gap
    if normal_model == 'pitois':
        c *= pitois_volume_factor(r_bar, gap, bridge_volume)
    return c


def viscous_decay_time(radius1, density, viscosity, s_min, radius2=None, wall=False,
                       normal_model='adamsPerchard', bridge_volume=None):
    """Viscous decay time t_v = m*/C^n(S_min) (P12).

    Adams–Perchard (P4): t_v = m* S_min/(6πμ r̄²); for equal spheres t_v = (4/9) ρ r S_min/μ,
    against a wall (2/9) ρ r S_min/μ.  Pitois (P5, needs ``bridge_volume`` V): t_v is larger by
    1/[1 − (1 + V/(π r̄ S_min²))^(−1/2)]².  The explicit pair is stable iff Δt < 2 t_v and does not
    rebound spuriously iff Δt ≤ t_v.  Returns inf when μ = 0 or ``normal_model='none'``.
    ``radius2=None`` means two identical spheres (unless ``wall=True``).
    """
    f = 'viscous_decay_time'
    r1, r2 = _geometry(f, radius1, radius2, wall)
    rho = positive(f, 'density', density, ' [kg/m³]')
    mu = non_negative(f, 'viscosity', viscosity, ' [Pa·s]; 0 means dry')
    s = positive(f, 's_min', s_min, ' [m]')
    choice(f, 'normal_model', normal_model, NORMAL_MODELS)
    if normal_model == 'pitois':
        if bridge_volume is None:
            reject(f, 'bridge_volume', bridge_volume, "> 0 [m³] (required by normal_model='pitois')")
        bridge_volume = positive(f, 'bridge_volume', bridge_volume, ' [m³]')
    r_bar = reduced_radius(r1, r2)
    m_eff = reduced_mass(sphere_mass(r1, rho), None if r2 is None else sphere_mass(r2, rho))
    c = normal_coefficient(r_bar, mu, s, normal_model, bridge_volume)
    return m_eff / c if c > 0 else math.inf


def tangential_coefficients(radius1, viscosity, s, radius2=None, wall=False):
    """Goldman's small-gap coefficients at gap S (pass the clamped gap max(S, S_min)):

    C_T = 6πμ r̄ [(8/15) ln(r̄/S) + 0.9588]   (P8, translation)
    C_R = 6πμ r̄ [(2/15) ln(r̄/S) + 0.2526]   (P9, coupling; + sign, the paper's − is a misprint)
    C_W = 6πμ r̄ [(8/15) ln(r̄/S) + 0.5089]   (rotation, ``goldman`` model)

    Returns ``{'C_T': …, 'C_R': …, 'C_W': …}`` [N·s/m], unclamped (all positive for S < 2.6 r̄).
    """
    f = 'tangential_coefficients'
    r1, r2 = _geometry(f, radius1, radius2, wall)
    mu = non_negative(f, 'viscosity', viscosity, ' [Pa·s]')
    gap = positive(f, 's', s, ' [m]')
    r_bar = reduced_radius(r1, r2)
    return _goldman(6 * math.pi * mu * r_bar, r_bar, gap)


def _goldman(six_pi_mu_r, r_bar, gap):
    L = math.log(r_bar / gap)
    return {'C_T': six_pi_mu_r * (8.0 / 15.0 * L + 0.9588),
            'C_R': six_pi_mu_r * (2.0 / 15.0 * L + 0.2526),
            'C_W': six_pi_mu_r * (8.0 / 15.0 * L + 0.5089)}


def _tangential_weight(radius1, radius2, arm_gap):
    """P14a: 1 + 2.5 (a/r)² for the worst sphere side, arm a = r + arm_gap (3.5 for arms r)."""
    worst = max([1.0] + [(r + arm_gap) / r for r in (radius1, radius2) if r])
    return 1 + ROT * worst * worst


def viscous_step_coefficient(radius1, radius2, viscosity, s_min, normal_model='adamsPerchard',
                             tangential_model='slip', bridge_volume=None):
    """C_n + w_t C_t at S_min (P14, P14a): a bridge's largest damping as the time step sees it, the
    same number the C++ models' stepCoefficient() give (``ViscBridgePhys.viscousStepCoefficient``).
    ``radius2=None`` is a wall.  C_t: C_T for slip and goldman, max(C_T, C_R) for washino; w_t = 3.5,
    or 1 + 2.5 (1 + S_min/2r)² for slip (mid-gap arms)."""
    f = 'viscous_step_coefficient'
    r1 = positive(f, 'radius1', radius1, ' [m]')
    r2 = None if radius2 is None else positive(f, 'radius2', radius2, ' [m]')
    mu = non_negative(f, 'viscosity', viscosity, ' [Pa·s]')
    smin = positive(f, 's_min', s_min, ' [m]')
    choice(f, 'normal_model', normal_model, NORMAL_MODELS)
    choice(f, 'tangential_model', tangential_model, TANGENTIAL_MODELS)
    r_bar = reduced_radius(r1, r2)
    c = normal_coefficient(r_bar, mu, smin, normal_model, bridge_volume) if normal_model != 'none' else 0.0
    if tangential_model != 'none':
        g = _goldman(6 * math.pi * mu * r_bar, r_bar, smin)
        if tangential_model == 'slip':
            c += _tangential_weight(r1, r2 or 0.0, 0.5 * smin) * max(g['C_T'], 0.0)
        elif tangential_model == 'washino':
            c += 3.5 * max(g['C_T'], g['C_R'], 0.0)
        else:
            c += 3.5 * max(g['C_T'], 0.0)
    return c

