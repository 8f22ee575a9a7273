"""Time-step planning for ViscBridge simulations, in plain Python (no YADE needed).

Which time step Δt does a DEM simulation with highly viscous liquid bridges need?  Two families of
limits compete (physics.md §3; equation tags P4…P15 as in the code comments of the C++ kernels):

* the **collision** limits of the dry Hertz–Mindlin contact: the Rayleigh-wave step (the usual
  DEM criterion) and the stability of the contact spring at the stiffness reached in a collision;
* the **viscous** limits of the bridges' dashpots.  YADE's leapfrog evaluates every
  velocity-dependent force from the stored velocity v_{n−1/2}, i.e. explicit Euler in velocity, so
  a dashpot C acting on a reduced mass m* multiplies the relative velocity by (1 − Δt C/m*) per
  step: stable iff Δt < 2 m*/C, free of spurious rebound iff Δt ≤ m*/C.  The coefficient is largest
  at the smallest gap the model allows, S_min (P6), so every viscous limit is proportional to
  S_min/μ and can be many orders of magnitude below the collision limit.

:func:`critical_dt` evaluates all of them for one representative contact and returns a
:class:`TimeStepCriteria` (a table of :class:`Bound` rows) with the stable step, the step free of
spurious rebounds, the governing bound and the regime.  The building blocks are public:

=============================  =================================================================
:func:`rayleigh_time`          T_R = π r √(ρ/G) / (0.1631 ν + 0.876605), G = E/(2(1+ν))
:func:`rayleigh_dt`            fraction · T_R (fraction 0.2 by default)
:func:`hertz_collision_time`   t_c = 2.868 (m*²/(r̄ E*² v))^(1/5)
:func:`viscous_decay_time`     t_v = m*/C^n(S_min)                                          (P12)
:func:`normal_coefficient`     C^n(S) of Adams–Perchard (P4) or Pitois (P5)
:func:`tangential_coefficients` C_T, C_R, C_W of Goldman et al. (P8, P9, C_W)
:func:`pair_limit`             4m*/(C + √(C² + 4m*k))                                       (P13)
:func:`network_limit`          4/(d + √(d² + 4κ))                                           (P14)
=============================  =================================================================

Conventions (physics.md §1): r̄ = r_i r_j/(r_i + r_j), m* = m_i m_j/(m_i + m_j); against a wall
r̄ = r and m* = m.  All quantities in SI units.  The constants are those of the C++ kernels
(``pkg/viscbridge/physics/*.hpp``): same E*, G*, Hertz and Mindlin stiffnesses as YADE's
``Ip2_FrictMat_FrictMat_MindlinPhys``, same viscous coefficients as the ViscBridge laws.
"""
import math
from dataclasses import dataclass, field

from ._checks import choice, in_range, integer, non_negative, number, positive, reject
from . import _registry

__all__ = ['Bound', 'TimeStepCriteria', 'critical_dt', 'rayleigh_time', 'rayleigh_dt',
           'hertz_collision_time', 'hertz_max_overlap', 'hertz_normal_stiffness',
           'mindlin_tangential_stiffness', 'effective_young', 'effective_shear',
           'viscous_decay_time', 'normal_coefficient', 'pitois_volume_factor',
           'tangential_coefficients', 'pair_limit', 'network_limit', 'restitution_damping_ratio',
           'reduced_radius', 'reduced_mass', 'sphere_mass', 'sphere_volume', 'viscous_step_coefficient',
           'rupture_distance', 'capillary_force', 'capillary_stiffness', 'capillary_max_stiffness', 'lattice_limit',
           'NORMAL_MODELS', 'TANGENTIAL_MODELS', 'CAPILLARY_MODELS', 'INTEGRATIONS']

# The model names are those the C++ registry lists (physics/SubModels.hpp, via _registry.py).
NORMAL_MODELS = _registry.SLOTS['normalModel']['models']
TANGENTIAL_MODELS = _registry.SLOTS['tangentialModel']['models']
CAPILLARY_MODELS = _registry.SLOTS['capillaryModel']['models']
INTEGRATIONS = _registry.INTEGRATIONS

#: Rayleigh-wave constants (Thornton 2000 after Miller & Pursey 1955), as YADE's
#: ``utils.RayleighWaveTimeStep`` (Shop::RayleighWaveTimeStep).
RAYLEIGH_A, RAYLEIGH_B = 0.1631, 0.876605
#: Hertz collision duration t_c = HERTZ_TC · (m*²/(r̄ E*² v))^(1/5) (= 2.9432·(15/16)^(2/5)).
HERTZ_TC = 2.868
#: Ratio of a sphere's rotational to translational mobility seen at its surface: r²/I · m = 5/2.
ROT = 2.5


# ------------------------------------------------------------------------------------------------
# argument checks: every failure is a ValueError naming the parameter, its value and the range
# ------------------------------------------------------------------------------------------------
def _poisson(func, value, name='poisson'):
    allowed = '(-1, 0.5)'
    x = number(func, name, value, allowed)
    if not -1 < x < 0.5:
        reject(func, name, value, allowed)
    return x


def _gap_and_volume(func, r_bar, particle_volume, s_min, s_min_rel, bridge_volume, bridge_volume_rel):
    """S_min and V as the Ip2 fills them in (sMin or sMinRel · r̄, bridgeVolume or bridgeVolumeRel × the
    mean particle volume), checked."""
    if s_min is None:
        smin = in_range(func, 's_min_rel', s_min_rel, 0, 1, lo_open=True, unit=' (S_min / r̄)') * r_bar
    else:
        smin = positive(func, 's_min', s_min, ' [m]')
    if bridge_volume is None:
        vrel = in_range(func, 'bridge_volume_rel', bridge_volume_rel, 0, 1, lo_open=True,
                        unit=' (fraction of the particle volume)')
        volume = vrel * particle_volume
    else:
        volume = positive(func, 'bridge_volume', bridge_volume, ' [m³]')
    return smin, volume


def _geometry(func, radius1, radius2, wall):
    """(r1, r2) checked; r2 is None against a wall, r1 when radius2 is None (identical spheres)."""
    r1 = positive(func, 'radius1' if func != 'critical_dt' else 'radius', radius1, ' [m]')
    if not isinstance(wall, bool):
        reject(func, 'wall', wall, 'True or False')
    if wall:
        if radius2 is not None:
            reject(func, 'radius2', radius2, 'None when wall=True (a wall has no radius)')
        return r1, None
    r2 = r1 if radius2 is None else positive(func, 'radius2', radius2, ' [m]')
    return r1, r2


# ------------------------------------------------------------------------------------------------
# geometry and material (physics.md §1; PairGeometry.hpp, HertzMindlin.hpp)
# ------------------------------------------------------------------------------------------------
def sphere_volume(radius):
    """(4/3) π r³."""
    return 4.0 / 3.0 * math.pi * radius ** 3


def sphere_mass(radius, density):
    """ρ (4/3) π r³."""
    return density * sphere_volume(radius)


def reduced_radius(radius1, radius2=None):
    """r̄ = r₁r₂/(r₁ + r₂) (§1); ``radius2=None`` is a wall: r̄ = r₁ (PairGeometry.hpp)."""
    if radius2 is None:
        return radius1
    return radius1 * radius2 / (radius1 + radius2)


def reduced_mass(mass1, mass2=None):
    """m* = m₁m₂/(m₁ + m₂) (§1); ``mass2=None`` is a wall (infinite mass): m* = m₁."""
    if mass2 is None:
        return mass1
    return mass1 * mass2 / (mass1 + mass2)


def effective_young(young1, poisson1, young2=None, poisson2=None):
    """E* from 1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂ (second material defaults to the first).

    Written as YADE's Ip2_FrictMat_FrictMat_MindlinPhys: E* = E₁E₂/((1−ν₁²)E₂ + (1−ν₂²)E₁); for
    identical materials E* = E/(2(1−ν²)).  Hertz: F = (4/3) E* √r̄ δ^(3/2).
    """
    if young2 is None:
        young2, poisson2 = young1, poisson1
    return young1 * young2 / ((1 - poisson1 ** 2) * young2 + (1 - poisson2 ** 2) * young1)


def effective_shear(young1, poisson1, young2=None, poisson2=None):
    """G* from 1/G* = (2−ν₁)/G₁ + (2−ν₂)/G₂, G = E/(2(1+ν)), as YADE's Mindlin law.

    For identical materials G* = G/(2(2−ν)).  Mindlin tangent stiffness k_s = 8 G* √(r̄ δ).
    """
    if young2 is None:
        young2, poisson2 = young1, poisson1
    g1 = young1 / (2 * (1 + poisson1))
    g2 = young2 / (2 * (1 + poisson2))
    return 1.0 / ((2 - poisson1) / g1 + (2 - poisson2) / g2)


def hertz_max_overlap(m_eff, r_bar, e_star, velocity):
    """Maximum Hertz overlap of a head-on collision at approach speed v:
    δ_max = (15 m* v² / (16 E* √r̄))^(2/5) (kinetic energy ½m*v² = (8/15) E* √r̄ δ^(5/2))."""
    return (15.0 * m_eff * velocity ** 2 / (16.0 * e_star * math.sqrt(r_bar))) ** 0.4


def hertz_normal_stiffness(r_bar, e_star, overlap):
    """Hertz tangent stiffness k_n = dF/dδ = 2 E* √(r̄ δ) (YADE: 3/2 · kno · δ^(1/2), kno = (4/3)E*√r̄)."""
    return 2.0 * e_star * math.sqrt(r_bar * overlap)


def mindlin_tangential_stiffness(r_bar, g_star, overlap):
    """Mindlin no-slip tangential stiffness k_s = 8 G* √(r̄ δ) (YADE: kso · δ^(1/2), kso = 8√r̄ G*)."""
    return 8.0 * g_star * math.sqrt(r_bar * overlap)


def restitution_damping_ratio(restitution):
    """Damping ratio β of YADE's Mindlin law for a restitution coefficient e (Thornton et al. 2013,
    (B6)–(B7); HertzMindlin.hpp ``dampingRatioFromRestitution``).  e = 1 gives 0.  The contact
    dashpots are c_n = 2β√(m* k_n), c_s = 2β√(m* k_s)."""
    e = number('restitution_damping_ratio', 'restitution', restitution, '(0, 1]')
    if not 0 < e <= 1:
        reject('restitution_damping_ratio', 'restitution', restitution, '(0, 1]')
    if e == 1.0:
        return 0.0
    h = (-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18,
         6276.757, -1489.915)
    poly = h[9]
    for c in reversed(h[:9]):
        poly = c + e * poly
    alpha = e * poly
    return math.sqrt(1.0 / (1.0 - (1.0 + e) ** 2 * math.exp(alpha)) - 1.0)


# ------------------------------------------------------------------------------------------------
# collision time scales
# ------------------------------------------------------------------------------------------------
def rayleigh_time(radius, density, young, poisson):
    """Rayleigh-wave time T_R = π r √(ρ/G) / (0.1631 ν + 0.876605), G = E/(2(1+ν)).

    The time a Rayleigh wave needs to cross a sphere (Thornton 2000), exactly as YADE's
    ``utils.RayleighWaveTimeStep()`` for one sphere.  0.2 T_R is the customary DEM collision step;
    at r = 0.5 mm, ρ = 2500 kg/m³, E = 1e7 Pa, ν = 0.3 it is 8.7e-6 s (physics.md §3), and it
    scales as E^(−1/2).
    """
    f = 'rayleigh_time'
    r = positive(f, 'radius', radius, ' [m]')
    rho = positive(f, 'density', density, ' [kg/m³]')
    e = positive(f, 'young', young, ' [Pa]')
    nu = _poisson(f, poisson)
    shear = e / (2 * (1 + nu))
    return math.pi * r * math.sqrt(rho / shear) / (RAYLEIGH_A * nu + RAYLEIGH_B)


def rayleigh_dt(radius, density, young, poisson, fraction=0.2):
    """The usual DEM collision step: fraction · T_R (see :func:`rayleigh_time`)."""
    fr = positive('rayleigh_dt', 'fraction', fraction)
    return fr * rayleigh_time(radius, density, young, poisson)


def hertz_collision_time(radius1, radius2, density, young, poisson, impact_velocity, wall=False):
    """Duration of a dry Hertz collision: t_c = 2.868 (m*² / (r̄ E*² v))^(1/5).

    E* = E/(2(1−ν²)) (identical materials; 1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂), r̄ and m* of §1; with
    ``wall=True`` (``radius2`` must then be None) r̄ = r and m* = m, the wall being of the same
    material.  Equivalently t_c = 2.9432 δ_max/v.  A time scale, not a stability limit.
    """
    f = 'hertz_collision_time'
    r1, r2 = _geometry(f, radius1, radius2, wall)
    rho = positive(f, 'density', density, ' [kg/m³]')
    e = positive(f, 'young', young, ' [Pa]')
    nu = _poisson(f, poisson)
    v = positive(f, 'impact_velocity', impact_velocity, ' [m/s]')
    r_bar = reduced_radius(r1, r2)
    m_eff = reduced_mass(sphere_mass(r1, rho), None if r2 is None else sphere_mass(r2, rho))
    e_star = effective_young(e, nu)
    return HERTZ_TC * (m_eff ** 2 / (r_bar * e_star ** 2 * v)) ** 0.2


# ------------------------------------------------------------------------------------------------
# viscous coefficients (NormalViscous.hpp, GoldmanCoefficients.hpp)
# ------------------------------------------------------------------------------------------------
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


def rupture_distance(bridge_volume, contact_angle=0.0):
    """P11 (Lian et al. 1993): S_rup = (1 + θ/2) V^(1/3)."""
    return (1.0 + 0.5 * contact_angle) * bridge_volume ** (1.0 / 3.0)


def _capillary(model, r_bar, surface_tension, contact_angle, bridge_volume):
    """(force, stiffness) functions of the gap for a capillary model (physics.md §8), with the
    Derjaguin radius R = 2 r̄; the same formulas as physics/Capillary.hpp."""
    choice('capillary_force', 'model', model, CAPILLARY_MODELS)
    R = 2 * r_bar
    if model == 'willett':  # P19
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
    if model == 'rabinovich':  # P20
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
    return (lambda S: 0.0), (lambda S: 0.0)


def capillary_force(model, r_bar, surface_tension, contact_angle, bridge_volume, gap):
    """The capillary pull [N] at gap S (P19 'willett', P20 'rabinovich'; held at its contact value
    in overlap).  r̄ is the reduced radius (a sphere's radius against a wall)."""
    return _capillary(model, r_bar, surface_tension, contact_angle, bridge_volume)[0](gap)


def capillary_stiffness(model, r_bar, surface_tension, contact_angle, bridge_volume, gap):
    """|dF/dS| of the capillary pull at gap S (P22; 0 in overlap) [N/m]."""
    return _capillary(model, r_bar, surface_tension, contact_angle, bridge_volume)[1](gap)


def capillary_max_stiffness(model, r_bar, surface_tension, contact_angle, bridge_volume, s_rup):
    """The largest |dF/dS| over 0 < S ≤ S_rup (P22), as the time step takes it: Willett's in closed
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


# ------------------------------------------------------------------------------------------------
# the stability formulas
# ------------------------------------------------------------------------------------------------
def pair_limit(m_eff, damping, stiffness):
    """P13: Δt < 4m*/(C + √(C² + 4m*k)) for a spring k and a dashpot C (explicit in velocity).

    k → 0 gives 2m*/C = 2 t_v, C → 0 gives 2√(m*/k).  In terms of ω₀ = √(k/m*) and the damping
    ratio ζ = C/(2√(m*k)): ω₀Δt < 2(√(1+ζ²) − ζ) (R5).  min(2√(m*/k), 2m*/C) overestimates it by up
    to the golden ratio 1.618, reached at ζ = 1/2.
    """
    if damping == 0 and stiffness == 0:
        return math.inf
    return 4.0 * m_eff / (damping + math.sqrt(damping * damping + 4.0 * m_eff * stiffness))


def network_limit(d, kappa):
    """P14: Δt ≤ 4/(d + √(d² + 4κ)) with d = Σ_j (C_n + 3.5 C_t)(1/m_i + 1/m_j) and
    κ = Σ_j (k_n + 3.5 k_t)(1/m_i + 1/m_j).  Dashpots only (κ = 0): 2/d; springs only: 2/√κ."""
    if d == 0 and kappa == 0:
        return math.inf
    return 4.0 / (d + math.sqrt(d * d + 4.0 * kappa))


# ------------------------------------------------------------------------------------------------
# the spectral limit of a regular packing (physics.md §7, P16–P18)
# ------------------------------------------------------------------------------------------------
#: Bond vectors (one of each ± pair) of the Bravais lattices of equal touching spheres, in units of
#: the sphere diameter: simple cubic (z = 6), body-centred cubic (z = 8), face-centred cubic (z = 12).
LATTICE_BONDS = {
    6: [(1, 0, 0), (0, 1, 0), (0, 0, 1)],
    8: [(s1 / math.sqrt(3), s2 / math.sqrt(3), 1 / math.sqrt(3)) for s1 in (1, -1) for s2 in (1, -1)],
    12: [tuple(v / math.sqrt(2) for v in b) for b in ((1, 1, 0), (1, -1, 0), (1, 0, 1), (1, 0, -1), (0, 1, 1), (0, 1, -1))],
}


def _bond_block(n, cn, m, a1, a2):
    """The 12×12 map (v1, ω1, v2, ω2) → (force, torque on 1, force, torque on 2) of one bridge, as
    physics/ViscousBlock.hpp's bridgeResistance: u = (I − nnᵀ)(v1 − v2), s = (a1 ω1 + a2 ω2) × n,
    F = cn (n·dv) n + m11 u + m12 s, G = m21 u + m22 s, torques a_k n × G."""
    import numpy as np
    n = np.asarray(n, float)
    N = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])  # N v = n × v
    P = np.eye(3) - np.outer(n, n)
    m11, m12, m21, m22 = m
    # dv = v1 − v2, s = −N (a1 ω1 + a2 ω2) (since (a ω) × n = −n × (a ω))
    Jdv = np.hstack([np.eye(3), np.zeros((3, 3)), -np.eye(3), np.zeros((3, 3))])
    Js = np.hstack([np.zeros((3, 3)), -a1 * N, np.zeros((3, 3)), -a2 * N])
    F = cn * np.outer(n, n) @ Jdv + m11 * P @ Jdv + m12 * Js
    G = m21 * P @ Jdv + m22 * Js
    return np.vstack([F, a1 * N @ G, -F, a2 * N @ G])


def lattice_limit(radius, density, viscosity, coordination=12, *, s_min=None, s_min_rel=1e-3, bridge_volume=None,
                  bridge_volume_rel=0.01, normal_model='adamsPerchard', tangential_model='slip', spring=0.0,
                  tangential_spring=None, q_points=12):
    """The explicit scheme's stability limit on an infinite regular packing of equal spheres, every
    contact a bridge held at S_min (the stiffest state), as ViscBridgeTimeStepper computes it on a
    live network (P18, with its safety 1): the smallest h with λ_max(h²K̃ + 2hD̃) = 4, the spectrum
    taken over the Bloch waves of the lattice (a q grid of q_points³ in the Brillouin zone).

    coordination: 6 (simple cubic), 8 (bcc) or 12 (fcc).  spring / tangential_spring [N/m]: an
    optional contact stiffness per bond (default: none, the viscous regime).  Returns a dict with
    'h' [s], 'pair_limit' (2 t_v of one bridge, P12) and 'network_bound' (P14), so the three can be
    compared: P14 ≤ h ≤ pair_limit.

    The limit of a perfect lattice, not a planning value for a random bed: the study's wetted random
    bed (μ = 1 Pa·s, z = 4.5) was measured unstable above 1.016e-7 s, below this function's
    1.376e-7 s for the simple cubic lattice (z = 6) of the same spheres — a random bed's top mode
    is local, on a cluster stiffer than its mean coordination.  Plan with :func:`critical_dt`
    (P14, rigorous) and let ViscBridgeTimeStepper find a live bed's own limit."""
    import numpy as np
    from scipy.optimize import brentq
    f = 'lattice_limit'
    r = positive(f, 'radius', radius, ' [m]')
    rho = positive(f, 'density', density, ' [kg/m³]')
    mu = non_negative(f, 'viscosity', viscosity, ' [Pa·s]')
    if coordination not in LATTICE_BONDS:
        reject(f, 'coordination', coordination, ', '.join(str(z) for z in LATTICE_BONDS))
    choice(f, 'normal_model', normal_model, NORMAL_MODELS)
    choice(f, 'tangential_model', tangential_model, TANGENTIAL_MODELS)
    r_bar = r / 2
    smin, volume = _gap_and_volume(f, r_bar, sphere_volume(r), s_min, s_min_rel, bridge_volume, bridge_volume_rel)
    spring = non_negative(f, 'spring', spring, ' [N/m]')
    if tangential_spring is not None:
        tangential_spring = non_negative(f, 'tangential_spring', tangential_spring, ' [N/m]')
    q_points = integer(f, 'q_points', q_points, minimum=2)
    m = sphere_mass(r, rho)
    inertia = 0.4 * m * r * r
    cn = normal_coefficient(r_bar, mu, smin, normal_model, volume) if normal_model != 'none' else 0.0
    g = _goldman(6 * math.pi * mu * r_bar, r_bar, smin)
    resistance = {'none': (0, 0, 0, 0), 'slip': (g['C_T'],) * 4, 'washino': (g['C_T'], g['C_R'], g['C_T'], g['C_R']),
                  'goldman': (g['C_T'], g['C_R'], g['C_R'], g['C_W'])}[tangential_model]
    arm = r + (0.5 * smin if tangential_model == 'slip' else 0.0)
    kt = spring if tangential_spring is None else tangential_spring
    scale = np.repeat([1 / math.sqrt(m), 1 / math.sqrt(inertia)], 3)
    bonds = [np.array(b, float) for b in LATTICE_BONDS[coordination]]
    blocks = [(b, _bond_block(b, cn, resistance, arm, arm), _bond_block(b, spring, (kt,) * 4, r, r)) for b in bonds]

    qs = np.linspace(-math.pi / (2 * r), math.pi / (2 * r), q_points)
    q = np.stack(np.meshgrid(qs, qs, qs, indexing='ij'), axis=-1).reshape(-1, 3)
    S = np.outer(scale, scale)

    def bloch(pick):
        """D̃(q) or K̃(q) for every q: particle i is body 1 of its bond to i + b and body 2 of the one from i − b."""
        out = np.zeros((len(q), 6, 6), complex)
        for b, *maps in blocks:
            B = maps[pick]
            phase = np.exp(1j * 2 * r * (q @ b))[:, None, None]
            out += B[:6, :6] + B[6:, 6:] + B[:6, 6:] * phase + B[6:, :6] / phase
        return out * S
    Ds, Ks = bloch(0), bloch(1)

    def excess(h):  # the top of the spectrum over every q at once, minus 4
        return np.linalg.eigvalsh(h * h * Ks + 2 * h * Ds).max() - 4

    d14 = coordination * viscous_step_coefficient(r, r, mu, smin, normal_model, tangential_model, volume) * 2 / m
    k14 = coordination * (spring + 3.5 * kt) * 2 / m
    p14 = network_limit(d14, k14)
    if not math.isfinite(p14):  # neither dashpots nor springs: nothing limits the step
        return dict(h=math.inf, pair_limit=pair_limit(m / 2, cn, spring), network_bound=p14)
    # P14 is below the root (rigorous); the bracket is grown from it, then Brent's method
    lo = p14
    while excess(lo) >= 0:
        lo /= 2
    hi = 2 * lo
    while excess(hi) < 0:
        lo, hi = hi, 2 * hi
    h = brentq(excess, lo, hi, xtol=lo * 1e-13, rtol=1e-12)
    return dict(h=h, pair_limit=pair_limit(m / 2, cn, spring), network_bound=p14)


# ------------------------------------------------------------------------------------------------
# the report
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Bound:
    """One time-step limit.

    kind: 'stability' (Δt above it diverges), 'design' (stable, but an approaching pair rebounds
    spuriously above it) or 'info' (a time scale, not a limit).  regime: 'viscous' when the limit is
    set by a bridge's viscous coefficient, 'collision' when by the dry contact; for the combined
    bounds (P13, P14) the part that dominates (viscous iff the dashpot-only limit is the smaller).
    """
    name: str
    value: float
    kind: str
    formula: str
    regime: str = ''


@dataclass
class TimeStepCriteria:
    """The result of :func:`critical_dt`: every bound, and what they imply.

    stability_limit   min over 'stability' bounds: the largest stable Δt (apply a safety factor)
    no_rebound_limit  min(stability_limit, min over 'design' bounds)
    governing         name of the bound attaining stability_limit
    regime            'viscous' or 'collision': which physics sets the governing bound
    parameters        the inputs, after defaults (S_min, V) were filled in
    derived           r̄, m*, E*, G*, δ_max, k_n, k_t, C^n, C_T, C_R, C_W, t_v, ... (SI units)
    """
    bounds: list
    parameters: dict = field(default_factory=dict)
    derived: dict = field(default_factory=dict)
    stability_limit: float = field(init=False)
    no_rebound_limit: float = field(init=False)
    governing: str = field(init=False)
    regime: str = field(init=False)

    def __post_init__(self):
        stab = [b for b in self.bounds if b.kind == 'stability']
        best = min(stab, key=lambda b: b.value)  # first of equal values: table order
        self.stability_limit = best.value
        self.governing = best.name
        self.regime = best.regime
        design = [b.value for b in self.bounds if b.kind == 'design']
        self.no_rebound_limit = min([self.stability_limit] + design)

    def bound(self, name):
        """The :class:`Bound` called ``name`` (KeyError when it is not in the table)."""
        for b in self.bounds:
            if b.name == name:
                return b
        raise KeyError('no bound %r; bounds: %s' % (name, ', '.join(b.name for b in self.bounds)))

    def names(self):
        return [b.name for b in self.bounds]

    def as_dict(self):
        """Plain-data view: dicts, lists, floats, strings (t_v is inf when there is no normal dashpot)."""
        return {'stability_limit': self.stability_limit, 'no_rebound_limit': self.no_rebound_limit,
                'governing': self.governing, 'regime': self.regime,
                'bounds': [{'name': b.name, 'value': b.value, 'kind': b.kind, 'regime': b.regime,
                            'formula': b.formula} for b in self.bounds],
                'parameters': dict(self.parameters), 'derived': dict(self.derived)}

    def __str__(self):
        p = self.parameters
        head = ('ViscBridge time-step criteria: %s, r = %s m%s, rho = %g kg/m3, E = %g Pa, nu = %g, '
                'mu = %g Pa.s, S_min = %.4g m, %s / %s, %s, z = %g, v = %g m/s' % (
                    'sphere-wall' if p['wall'] else 'sphere-sphere', _g(p['radius']),
                    '' if p['wall'] or p['radius2'] == p['radius'] else ' & %s m' % _g(p['radius2']),
                    p['density'], p['young'], p['poisson'], p['viscosity'], p['s_min'],
                    p['normal_model'], p['tangential_model'], p['integration'], p['coordination'],
                    p['impact_velocity']))
        w = max(len(b.name) for b in self.bounds)
        rows = ['  %-*s  %-10s  %-9s  %-9s  %s' % (w, 'bound', 'value [s]', 'kind', 'regime', 'formula')]
        for b in self.bounds:
            rows.append('  %-*s  %-10s  %-9s  %-9s  %s' % (w, b.name, '%.4g' % b.value, b.kind,
                                                           b.regime or '-', b.formula))
        tail = ['stability limit:  %.4g s  (governing: %s, regime: %s)' % (
                    self.stability_limit, self.governing, self.regime),
                'no-rebound limit: %.4g s' % self.no_rebound_limit]
        return '\n'.join([head] + rows + tail)

    def __repr__(self):
        return ('TimeStepCriteria(stability_limit=%.4g, no_rebound_limit=%.4g, governing=%r, regime=%r)'
                % (self.stability_limit, self.no_rebound_limit, self.governing, self.regime))


def _g(x):
    return '%g' % x


def _regime(bridge_dashpot_limit, elastic_limit):
    """Dominant part of a combined bound: viscous iff the bridge dashpots alone give the smaller limit."""
    return 'viscous' if bridge_dashpot_limit < elastic_limit else 'collision'


# ------------------------------------------------------------------------------------------------
# critical_dt
# ------------------------------------------------------------------------------------------------
def critical_dt(radius, density, young, poisson, viscosity, *, radius2=None, wall=False, s_min=None,
                s_min_rel=1e-3, bridge_volume=None, bridge_volume_rel=0.01,
                normal_model='adamsPerchard', tangential_model='slip', integration='explicit',
                coordination=1, impact_velocity=1.0, restitution=1.0, capillary_model='none', surface_tension=0.0):
    """All time-step bounds for one representative contact, as a :class:`TimeStepCriteria`.

    Geometry: two spheres of radii ``radius`` and ``radius2`` (default: equal), or one sphere and a
    wall of the same material (``wall=True``: r̄ = r, m* = m).  Both spheres have ``density``.

    Defaults as the Ip2 functor: S_min = ``s_min_rel`` · r̄ when ``s_min`` is None; V =
    ``bridge_volume_rel`` × the mean volume of the two spheres (against a wall: the sphere's
    volume) when ``bridge_volume`` is None (only used by ``normal_model='pitois'``).  viscosity = 0
    is dry: no viscous bound.  ``restitution`` is the dry contact's ``en`` (1: no contact damping).

    Bounds (C^n, C_T, C_R, C_W at S_min; k_n = 2E*√(r̄δ), k_t = 8G*√(r̄δ) at the maximum overlap
    δ_max = (15 m* v²/(16 E* √r̄))^(2/5) of a head-on collision at ``impact_velocity``):

    rayleigh             0.2 T_R                                  stability  (usual DEM criterion)
    hertz_collision      t_c                                      info
    elastic_pair         2√(m*/k_n)                               stability  (P13, C = 0)
    viscous_pair         2 t_v = 2 m*/C^n                         stability  (P12)
    viscous_no_rebound   t_v                                      design     (P12)
    coupled_pair         4m*/(C + √(C² + 4m*k_n)), C = C^n + c_n  stability  (P13)
    tangential_*         per tangential model (§3 "Tangential pair")  stability
                         slip:    2m*/((1+β)C_T) ≈ 0.571 m*/C_T, β = 2.5 (1 + S_min/2r)² (mid-gap arms)
                         washino: 2m*/(C_T + 2.5 C_R) and 0.8 m*/C_R
                         goldman: 2m*/C_T, 0.8 m*/C_W and the exact 2/λ_max of
                                  [[C_T, C_R], [2.5 C_R, 2.5 C_W]]/m*
    network              4/(d + √(d² + 4κ)), z contacts per particle              stability (P14)
    network_dashpot      2/d                                      stability  (P14)
    network_no_reversal  1/d                                      design     (P14)

    with d = z (C^n + c_n + w_t (C_t + c_s))(1/m_i + 1/m_j), κ = z (k_n + 3.5 k_t)(1/m_i + 1/m_j),
    1/m_j = 0 for a wall, C_t = C_T (slip, goldman), max(C_T, C_R) (washino), 0 (none); w_t = 3.5,
    or 1 + 2.5 (1 + S_min/2r)² for slip (its torque arms reach the mid-gap point).  c_n, c_s are
    the contact dashpots of ``restitution`` < 1.

    ``integration='implicit'`` (P15: backward Euler for the bridges, unconditionally stable for the
    viscous part) drops every bound set by a bridge coefficient and uses C = 0 (bridges) in P13/P14.
    """
    f = 'critical_dt'
    r1, r2 = _geometry(f, radius, radius2, wall)
    rho = positive(f, 'density', density, ' [kg/m³]')
    e = positive(f, 'young', young, ' [Pa]')
    nu = _poisson(f, poisson)
    mu = non_negative(f, 'viscosity', viscosity, ' [Pa·s]; 0 means dry')
    choice(f, 'normal_model', normal_model, NORMAL_MODELS)
    choice(f, 'tangential_model', tangential_model, TANGENTIAL_MODELS)
    choice(f, 'integration', integration, INTEGRATIONS)
    z = number(f, 'coordination', coordination, '>= 1 (contacts per particle)')
    if not z >= 1:
        reject(f, 'coordination', coordination, '>= 1 (contacts per particle)')
    v = positive(f, 'impact_velocity', impact_velocity, ' [m/s]')
    choice(f, 'capillary_model', capillary_model, CAPILLARY_MODELS)
    gamma = non_negative(f, 'surface_tension', surface_tension, ' [N/m]')
    en = number(f, 'restitution', restitution, '(0, 1]')
    if not 0 < en <= 1:
        reject(f, 'restitution', restitution, '(0, 1]')

    r_bar = reduced_radius(r1, r2)
    m1 = sphere_mass(r1, rho)
    m2 = None if r2 is None else sphere_mass(r2, rho)
    m_eff = reduced_mass(m1, m2)
    inv_m = 1.0 / m1 + (0.0 if m2 is None else 1.0 / m2)  # 1/m_i + 1/m_j, = 1/m* (P14)

    v1 = sphere_volume(r1)
    v2 = v1 if r2 is None else sphere_volume(r2)
    smin, volume = _gap_and_volume(f, r_bar, 0.5 * (v1 + v2), s_min, s_min_rel, bridge_volume, bridge_volume_rel)

    # ---- dry contact ------------------------------------------------------------------------------
    e_star = effective_young(e, nu)
    g_star = effective_shear(e, nu)
    t_r = rayleigh_time(min(r1, r2) if r2 is not None else r1, rho, e, nu)
    t_c = hertz_collision_time(r1, r2, rho, e, nu, v, wall=wall)
    delta = hertz_max_overlap(m_eff, r_bar, e_star, v)
    k_n = hertz_normal_stiffness(r_bar, e_star, delta)
    k_t = mindlin_tangential_stiffness(r_bar, g_star, delta)
    beta_c = restitution_damping_ratio(en)
    c_n_contact = 2 * beta_c * math.sqrt(m_eff * k_n)
    c_s_contact = 2 * beta_c * math.sqrt(m_eff * k_t)

    # ---- bridge coefficients at S_min (P4/P5, P8, P9, C_W; clamped as the kernels) ----------------
    wet = mu > 0
    explicit = integration == 'explicit'
    c_n = normal_coefficient(r_bar, mu, smin, normal_model, volume) if wet else 0.0
    g = _goldman(6 * math.pi * mu * r_bar, r_bar, smin)
    c_T, c_R, c_W = g['C_T'], g['C_R'], g['C_W']
    # arms of the rotational terms: r_k, or r_k + S_min/2 for slip (mid-gap point); the largest
    # rotational mobility over S ≤ S_min is at S = S_min (the coefficients are constant below it).
    arm_gap = 0.5 * smin if tangential_model == 'slip' else 0.0
    sides = [(r1, m1)] + ([] if r2 is None else [(r2, m2)])
    beta_rot = m_eff * sum(ROT * ((r + arm_gap) / r) ** 2 / m for r, m in sides)  # = 2.5 for r_k arms
    w_rot = 1 + ROT * max(((r + arm_gap) / r) ** 2 for r, _ in sides)              # P14 weight, 3.5
    if tangential_model == 'slip':
        c_T = max(c_T, 0.0)
        c_t_net = c_T
    elif tangential_model == 'washino':
        c_t_net = max(c_T, c_R)
    elif tangential_model == 'goldman':
        c_T, c_W = max(c_T, 0.0), max(c_W, 0.0)
        lim = math.sqrt(c_T * c_W)
        c_R = min(max(c_R, -lim), lim)
        c_t_net = c_T
    else:
        c_t_net = 0.0
    tangential_on = wet and tangential_model != 'none'
    if not tangential_on:
        c_t_net = 0.0
    viscous_active = wet and explicit and (c_n > 0 or tangential_on)
    # bridge dashpots seen by the explicit scheme (0 under P15)
    cb_n = c_n if explicit else 0.0
    cb_t = c_t_net if explicit else 0.0

    bounds = [
        Bound('rayleigh', 0.2 * t_r, 'stability',
              '0.2 T_R, T_R = pi r sqrt(rho/G)/(0.1631 nu + 0.876605)', 'collision'),
        Bound('hertz_collision', t_c, 'info', 't_c = 2.868 (m*^2/(rbar E*^2 v))^(1/5)'),
        Bound('elastic_pair', 2 * math.sqrt(m_eff / k_n), 'stability',
              '2 sqrt(m*/k_n), k_n = 2 E* sqrt(rbar delta_max) (P13, C = 0)', 'collision'),
    ]
    t_v = m_eff / c_n if c_n > 0 else math.inf
    if explicit and wet and c_n > 0:
        bounds += [Bound('viscous_pair', 2 * t_v, 'stability', '2 t_v = 2 m*/C^n(S_min) (P12)', 'viscous'),
                   Bound('viscous_no_rebound', t_v, 'design', 't_v = m*/C^n(S_min) (P12)', 'viscous')]
    c_pair = cb_n + c_n_contact
    bounds.append(Bound(
        'coupled_pair', pair_limit(m_eff, c_pair, k_n), 'stability',
        '4m*/(C + sqrt(C^2 + 4 m* k_n)), C = %s%s (P13)' % (
            'C^n(S_min)' if cb_n > 0 else '0 (implicit bridges)' if wet and not explicit else '0',
            ' + c_n(en)' if c_n_contact > 0 else ''),
        _regime(2 * m_eff / cb_n if cb_n > 0 else math.inf, 2 * math.sqrt(m_eff / k_n))))

    if explicit and tangential_on and c_T > 0:  # C_T > 0 for S_min < 6 r̄
        if tangential_model == 'slip':
            bounds.append(Bound('tangential_slip', 2 * m_eff / ((1 + beta_rot) * c_T), 'stability',
                                '2m*/((1+beta) C_T), beta = 2.5(1 + S_min/2r)^2 (~0.571 m*/C_T)', 'viscous'))
        elif tangential_model == 'washino':
            bounds.append(Bound('tangential_coupled', 2 * m_eff / (c_T + ROT * c_R), 'stability',
                                '2m*/(C_T + 2.5 C_R) (P13c)', 'viscous'))
            if c_R > 0:  # C_R > 0 for S_min < 6.6 r̄
                bounds.append(Bound('tangential_rotation', 2 * m_eff / (ROT * c_R), 'stability',
                                    '0.8 m*/C_R', 'viscous'))
        else:  # goldman: u' = -(C_T u + C_R s)/m*, s' = -2.5 (C_R u + C_W s)/m*
            a, b, c, dd = c_T, c_R, ROT * c_R, ROT * c_W
            lam = 0.5 * (a + dd) + math.sqrt(0.25 * (a - dd) ** 2 + b * c)
            bounds.append(Bound('tangential_translation', 2 * m_eff / c_T, 'stability', '2m*/C_T', 'viscous'))
            if c_W > 0:  # C_W > 0 for S_min < 2.6 r̄
                bounds.append(Bound('tangential_rotation', 2 * m_eff / (ROT * c_W), 'stability',
                                    '0.8 m*/C_W', 'viscous'))
            bounds.append(Bound('tangential_coupled', 2 * m_eff / lam, 'stability',
                                '2/lambda_max([[C_T, C_R], [2.5 C_R, 2.5 C_W]]/m*)', 'viscous'))

    d_bridge = z * (cb_n + w_rot * cb_t) * inv_m
    d = d_bridge + z * (c_n_contact + 3.5 * c_s_contact) * inv_m
    # the capillary pull, a spring of up to k_c along n (P22), with the stiffnesses of the contact
    k_c = (capillary_max_stiffness(capillary_model, r_bar, gamma, 0.0, volume, rupture_distance(volume))
           if capillary_model != 'none' and gamma > 0 else 0.0)
    if k_c > 0:
        bounds.append(Bound('capillary_spring', 2 * math.sqrt(m_eff / k_c), 'stability',
                            '2 sqrt(m*/k_c), k_c = max |dF/dS| of the capillary force (P22)', 'collision'))
    kappa = z * (k_n + 3.5 * k_t + k_c) * inv_m
    bounds.append(Bound(
        'network', network_limit(d, kappa), 'stability',
        '4/(d + sqrt(d^2 + 4 kappa)), d = z(C_n + %s C_t)(1/m_i+1/m_j), kappa = z(k_n + 3.5 k_t)(1/m_i+1/m_j) (P14)'
        % ('%.4g' % w_rot if tangential_model == 'slip' else '3.5'),
        _regime(2 / d_bridge if d_bridge > 0 else math.inf, 2 / math.sqrt(kappa))))
    if viscous_active:
        bounds += [Bound('network_dashpot', 2 / d, 'stability', '2/d (P14, dashpots only)', 'viscous'),
                   Bound('network_no_reversal', 1 / d, 'design', '1/d (P14, no reversal)', 'viscous')]

    parameters = dict(radius=r1, radius2=r2, wall=wall,
                      density=rho, young=e, poisson=nu, viscosity=mu, s_min=smin, bridge_volume=volume,
                      normal_model=normal_model, tangential_model=tangential_model,
                      integration=integration, coordination=z, impact_velocity=v, restitution=en,
                      capillary_model=capillary_model, surface_tension=gamma)
    derived = dict(r_bar=r_bar, m_eff=m_eff, mass1=m1, mass2=m2, e_star=e_star, g_star=g_star,
                   rayleigh_time=t_r, collision_time=t_c, max_overlap=delta, k_n=k_n, k_t=k_t,
                   contact_damping_ratio=beta_c, c_n_contact=c_n_contact, c_s_contact=c_s_contact,
                   C_n=c_n, C_T=c_T if tangential_on else 0.0, C_R=c_R if tangential_on else 0.0,
                   C_W=c_W if tangential_on else 0.0, t_v=t_v, network_d=d, network_kappa=kappa, k_capillary=k_c)
    return TimeStepCriteria(bounds=bounds, parameters=parameters, derived=derived)
