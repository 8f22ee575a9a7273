"""The spectral stability limit of a regular packing (physics.md §7, P16–P18): every contact of a
simple cubic, bcc or fcc lattice of equal spheres a bridge at S_min, the spectrum taken over the
lattice's Bloch waves (numpy, scipy).  A reference for ViscBridgeTimeStepper, not a planning value.
"""
import collections
import math

from .._checks import choice, integer, non_negative, positive, reject
from .bounds import network_limit, pair_limit
from .inputs import NORMAL_MODELS, TANGENTIAL_MODELS, _gap_and_volume
from .materials import sphere_mass, sphere_volume
from .viscous import _goldman, normal_coefficient, viscous_step_coefficient

__all__ = ['LATTICE_BONDS', 'lattice_limit']

#: Bond vectors (one of each ± pair) of the Bravais lattices of equal touching spheres, in units of
#: the sphere diameter: simple cubic (z = 6), body-centred cubic (z = 8), face-centred cubic (z = 12).
LATTICE_BONDS = {
    6: [(1, 0, 0), (0, 1, 0), (0, 0, 1)],
    8: [(s1 / math.sqrt(3), s2 / math.sqrt(3), 1 / math.sqrt(3)) for s1 in (1, -1) for s2 in (1, -1)],
    12: [tuple(v / math.sqrt(2) for v in b) for b in ((1, 1, 0), (1, -1, 0), (1, 0, 1), (1, 0, -1), (0, 1, 1), (0, 1, -1))],
}

#: A checked lattice_limit problem: the sphere (r, m, I), the liquid at S_min (mu, smin, volume),
#: the lattice and the models, the contact springs (kn, kt) and the q grid.
_Lattice = collections.namedtuple('_Lattice', 'r m inertia mu smin volume coordination normal_model tangential_model '
                                              'kn kt q_points')


def _bond_block(n, cn, m, a1, a2):
    """The 12×12 map (v1, ω1, v2, ω2) → (force, torque on 1, force, torque on 2) of one bridge, as
    core/linalg/ViscousBlock.hpp's bridgeResistance: u = (I − nnᵀ)(v1 − v2), s = (a1 ω1 + a2 ω2) × n,
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
    c = _checked_lattice(radius, density, viscosity, coordination, s_min, s_min_rel, bridge_volume, bridge_volume_rel,
                         normal_model, tangential_model, spring, tangential_spring, q_points)
    cn, resistance = _bond_resistance(c)
    d14 = c.coordination * viscous_step_coefficient(c.r, c.r, c.mu, c.smin, c.normal_model, c.tangential_model,
                                                    c.volume) * 2 / c.m
    k14 = c.coordination * (c.kn + 3.5 * c.kt) * 2 / c.m
    p14 = network_limit(d14, k14)
    limits = dict(pair_limit=pair_limit(c.m / 2, cn, c.kn), network_bound=p14)
    if not math.isfinite(p14):  # neither dashpots nor springs: nothing limits the step
        return dict(h=math.inf, **limits)
    return dict(h=_spectral_root(*_bloch_operators(c, cn, resistance), p14), **limits)


def _checked_lattice(radius, density, viscosity, coordination, s_min, s_min_rel, bridge_volume, bridge_volume_rel,
                     normal_model, tangential_model, spring, tangential_spring, q_points):
    """lattice_limit's arguments checked (in the order of its signature), S_min and V filled in as
    the Ip2 does, as a :data:`_Lattice`."""
    f = 'lattice_limit'
    r = positive(f, 'radius', radius, ' [m]')
    rho = positive(f, 'density', density, ' [kg/m³]')
    mu = non_negative(f, 'viscosity', viscosity, ' [Pa·s]')
    if coordination not in LATTICE_BONDS:
        reject(f, 'coordination', coordination, ', '.join(str(z) for z in LATTICE_BONDS))
    choice(f, 'normal_model', normal_model, NORMAL_MODELS)
    choice(f, 'tangential_model', tangential_model, TANGENTIAL_MODELS)
    smin, volume = _gap_and_volume(f, r / 2, sphere_volume(r), s_min, s_min_rel, bridge_volume, bridge_volume_rel)
    spring = non_negative(f, 'spring', spring, ' [N/m]')
    if tangential_spring is not None:
        tangential_spring = non_negative(f, 'tangential_spring', tangential_spring, ' [N/m]')
    q_points = integer(f, 'q_points', q_points, minimum=2)
    m = sphere_mass(r, rho)
    return _Lattice(r, m, 0.4 * m * r * r, mu, smin, volume, coordination, normal_model, tangential_model,
                    spring, spring if tangential_spring is None else tangential_spring, q_points)


def _bond_resistance(c):
    """(C^n, (m11, m12, m21, m22)) of one bridge at S_min: its normal coefficient and the tangential
    resistance of its model, as core/linalg/ViscousBlock.hpp has them."""
    r_bar = c.r / 2
    cn = normal_coefficient(r_bar, c.mu, c.smin, c.normal_model, c.volume) if c.normal_model != 'none' else 0.0
    g = _goldman(6 * math.pi * c.mu * r_bar, r_bar, c.smin)
    resistance = {'none': (0, 0, 0, 0), 'slip': (g['C_T'],) * 4, 'washino': (g['C_T'], g['C_R'], g['C_T'], g['C_R']),
                  'goldman': (g['C_T'], g['C_R'], g['C_R'], g['C_W'])}[c.tangential_model]
    return cn, resistance


def _bloch_operators(c, cn, resistance):
    """(D̃(q), K̃(q)): the mass-scaled 6×6 damping and stiffness of the lattice for every q of a
    q_points³ grid over the Brillouin zone (particle i is body 1 of its bond to i + b and body 2 of
    the one from i − b)."""
    import numpy as np
    r = c.r
    arm = r + (0.5 * c.smin if c.tangential_model == 'slip' else 0.0)
    scale = np.repeat([1 / math.sqrt(c.m), 1 / math.sqrt(c.inertia)], 3)
    bonds = [np.array(b, float) for b in LATTICE_BONDS[c.coordination]]
    blocks = [(b, _bond_block(b, cn, resistance, arm, arm), _bond_block(b, c.kn, (c.kt,) * 4, r, r)) for b in bonds]
    qs = np.linspace(-math.pi / (2 * r), math.pi / (2 * r), c.q_points)
    q = np.stack(np.meshgrid(qs, qs, qs, indexing='ij'), axis=-1).reshape(-1, 3)
    S = np.outer(scale, scale)

    def bloch(pick):
        out = np.zeros((len(q), 6, 6), complex)
        for b, *maps in blocks:
            B = maps[pick]
            phase = np.exp(1j * 2 * r * (q @ b))[:, None, None]
            out += B[:6, :6] + B[6:, 6:] + B[:6, 6:] * phase + B[6:, :6] / phase
        return out * S
    return bloch(0), bloch(1)


def _spectral_root(Ds, Ks, p14):
    """The smallest h with λ_max(h²K̃ + 2hD̃) = 4 over every q.  P14 is below the root (rigorous);
    the bracket is grown from it, then Brent's method."""
    import numpy as np
    from scipy.optimize import brentq

    def excess(h):  # the top of the spectrum over every q at once, minus 4
        return np.linalg.eigvalsh(h * h * Ks + 2 * h * Ds).max() - 4
    lo = p14
    while excess(lo) >= 0:
        lo /= 2
    hi = 2 * lo
    while excess(hi) < 0:
        lo, hi = hi, 2 * hi
    return brentq(excess, lo, hi, xtol=lo * 1e-13, rtol=1e-12)
