"""The stability formulas of the explicit scheme (physics.md §3): the limit of one pair with a
spring and a dashpot (P13) and Gershgorin's row-sum bound over a particle's contacts (P14).
Plain Python.
"""
import math

from .._checks import non_negative, positive

__all__ = ['pair_limit', 'network_limit']


def pair_limit(m_eff, damping, stiffness):
    """P13: Δt < 4m*/(C + √(C² + 4m*k)) for a spring k and a dashpot C (explicit in velocity).

    k → 0 gives 2m*/C = 2 t_v, C → 0 gives 2√(m*/k).  In terms of ω₀ = √(k/m*) and the damping
    ratio ζ = C/(2√(m*k)): ω₀Δt < 2(√(1+ζ²) − ζ) (R5).  min(2√(m*/k), 2m*/C) overestimates it by up
    to the golden ratio 1.618, reached at ζ = 1/2.
    """
    f = 'pair_limit'
    m_eff = positive(f, 'm_eff', m_eff, ' [kg]')
    damping = non_negative(f, 'damping', damping, ' [N·s/m]')
    stiffness = non_negative(f, 'stiffness', stiffness, ' [N/m]')
    if damping == 0 and stiffness == 0:
        return math.inf
    return 4.0 * m_eff / (damping + math.sqrt(damping * damping + 4.0 * m_eff * stiffness))


def network_limit(d, kappa):
    """P14: Δt ≤ 4/(d + √(d² + 4κ)) with d = Σ_j (C_n + 3.5 C_t)(1/m_i + 1/m_j) and
    κ = Σ_j (k_n + 3.5 k_t)(1/m_i + 1/m_j).  Dashpots only (κ = 0): 2/d; springs only: 2/√κ."""
    d = non_negative('network_limit', 'd', d, ' [1/s]')
    kappa = non_negative('network_limit', 'kappa', kappa, ' [1/s²]')
    if d == 0 and kappa == 0:
        return math.inf
    return 4.0 / (d + math.sqrt(d * d + 4.0 * kappa))

