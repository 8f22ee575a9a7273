"""Particles and their dry Hertz–Mindlin contact (physics.md §1, §3; PairGeometry.hpp,
HertzMindlin.hpp): sphere volume and mass, reduced radius and mass, effective moduli, Hertz and
Mindlin stiffnesses, the restitution damping ratio, and the collision time scales (Rayleigh-wave
step, Hertz collision time).  Plain Python.
"""
import math

from .._checks import in_range, number, positive, reject
from .inputs import _geometry, _poisson

__all__ = ['RAYLEIGH_A', 'RAYLEIGH_B', 'HERTZ_TC', 'sphere_volume', 'sphere_mass', 'reduced_radius',
           'reduced_mass', 'effective_young', 'effective_shear', 'hertz_max_overlap', 'hertz_normal_stiffness',
           'mindlin_tangential_stiffness', 'restitution_damping_ratio', 'rayleigh_time', 'rayleigh_dt',
           'hertz_collision_time']

#: Rayleigh-wave constants (Thornton 2000 after Miller & Pursey 1955), as YADE's
#: ``utils.RayleighWaveTimeStep`` (Shop::RayleighWaveTimeStep).
RAYLEIGH_A, RAYLEIGH_B = 0.1631, 0.876605
#: Hertz collision duration t_c = HERTZ_TC · (m*²/(r̄ E*² v))^(1/5) (= 2.9432·(15/16)^(2/5)).
HERTZ_TC = 2.868


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
    """The usual DEM collision step: fraction · T_R (see :func:`rayleigh_time`), fraction in (0, 1]."""
    fr = in_range('rayleigh_dt', 'fraction', fraction, 0, 1, lo_open=True)
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

