"""critical_dt: every time-step bound of one representative contact, in named steps — the checked
inputs and the pair's geometry, the dry contact, the bridge's coefficients at S_min, then the
collision and pair bounds (P12, P13), the tangential bounds of each model and the network bounds
(P14) — assembled into a :class:`~viscbridge.planning.report.TimeStepCriteria`.  Plain Python.
"""
import math
from types import SimpleNamespace

from .._checks import choice, non_negative, number, positive, reject
from .bounds import network_limit, pair_limit
from .capillary import capillary_max_stiffness, rupture_distance
from .inputs import CAPILLARY_MODELS, INTEGRATIONS, NORMAL_MODELS, TANGENTIAL_MODELS, _gap_and_volume, _geometry, _poisson
from .materials import (effective_shear, effective_young, hertz_collision_time, hertz_max_overlap, hertz_normal_stiffness,
                        mindlin_tangential_stiffness, rayleigh_time, reduced_mass, reduced_radius,
                        restitution_damping_ratio, sphere_mass, sphere_volume)
from .report import Bound, TimeStepCriteria, _regime
from .viscous import ROT, _goldman, normal_coefficient

__all__ = ['critical_dt']


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
    δ_max = (15 m* v²/(16 E* √r̄))^(2/5) of a head-on collision at ``impact_velocity``)::

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
    p = _checked_inputs(**locals())  # first: locals() holds exactly the arguments here
    dry = _dry_contact(p)
    bridge = _bridge_coefficients(p)
    network_bounds, network = _network_bounds(p, dry, bridge)
    bounds = _pair_bounds(p, dry, bridge) + _tangential_bounds(p, bridge) + network_bounds
    return TimeStepCriteria(bounds=bounds, parameters=_parameters(p), derived=_derived(p, dry, bridge, network))


# ---- the steps -----------------------------------------------------------------------------------
def _checked_inputs(radius, density, young, poisson, viscosity, radius2, wall, s_min, s_min_rel, bridge_volume,
                    bridge_volume_rel, normal_model, tangential_model, integration, coordination, impact_velocity,
                    restitution, capillary_model, surface_tension):
    """critical_dt's arguments checked (ValueError naming the first bad one, in this order), with the
    pair's geometry: r̄, masses, m*, 1/m_i + 1/m_j, S_min and V as the Ip2 fills them in."""
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
    p = SimpleNamespace(r1=r1, r2=r2, wall=wall, rho=rho, e=e, nu=nu, mu=mu, normal_model=normal_model,
                        tangential_model=tangential_model, integration=integration, z=z, v=v,
                        capillary_model=capillary_model, gamma=gamma, en=en,
                        wet=mu > 0, explicit=integration == 'explicit')
    _pair_geometry(p, s_min, s_min_rel, bridge_volume, bridge_volume_rel)
    return p


def _pair_geometry(p, s_min, s_min_rel, bridge_volume, bridge_volume_rel):
    """r̄, m₁, m₂ (None for a wall), m*, 1/m_i + 1/m_j (= 1/m*, P14), S_min and V into `p`."""
    p.r_bar = reduced_radius(p.r1, p.r2)
    p.m1 = sphere_mass(p.r1, p.rho)
    p.m2 = None if p.r2 is None else sphere_mass(p.r2, p.rho)
    p.m_eff = reduced_mass(p.m1, p.m2)
    p.inv_m = 1.0 / p.m1 + (0.0 if p.m2 is None else 1.0 / p.m2)
    v1 = sphere_volume(p.r1)
    v2 = v1 if p.r2 is None else sphere_volume(p.r2)
    p.smin, p.volume = _gap_and_volume('critical_dt', p.r_bar, 0.5 * (v1 + v2), s_min, s_min_rel, bridge_volume,
                                       bridge_volume_rel)


def _dry_contact(p):
    """The dry contact: E*, G*, T_R, t_c, δ_max, k_n and k_t at δ_max, the contact dashpots of `en`."""
    e_star = effective_young(p.e, p.nu)
    g_star = effective_shear(p.e, p.nu)
    delta = hertz_max_overlap(p.m_eff, p.r_bar, e_star, p.v)
    k_n = hertz_normal_stiffness(p.r_bar, e_star, delta)
    k_t = mindlin_tangential_stiffness(p.r_bar, g_star, delta)
    beta_c = restitution_damping_ratio(p.en)
    return SimpleNamespace(
        e_star=e_star, g_star=g_star, delta=delta, k_n=k_n, k_t=k_t, beta_c=beta_c,
        t_r=rayleigh_time(min(p.r1, p.r2) if p.r2 is not None else p.r1, p.rho, p.e, p.nu),
        t_c=hertz_collision_time(p.r1, p.r2, p.rho, p.e, p.nu, p.v, wall=p.wall),
        c_n_contact=2 * beta_c * math.sqrt(p.m_eff * k_n), c_s_contact=2 * beta_c * math.sqrt(p.m_eff * k_t))


def _slip_coefficients(c_T, c_R, c_W):
    c_T = max(c_T, 0.0)
    return c_T, c_R, c_W, c_T


def _washino_coefficients(c_T, c_R, c_W):
    return c_T, c_R, c_W, max(c_T, c_R)


def _goldman_coefficients(c_T, c_R, c_W):
    c_T, c_W = max(c_T, 0.0), max(c_W, 0.0)
    lim = math.sqrt(c_T * c_W)
    return c_T, min(max(c_R, -lim), lim), c_W, c_T


#: Per tangential model: (C_T, C_R, C_W) clamped as its kernel clamps them, and the C_t of P14.
_CLAMPED = {'slip': _slip_coefficients, 'washino': _washino_coefficients, 'goldman': _goldman_coefficients}


def _bridge_coefficients(p):
    """The bridge at S_min (P4/P5, P8, P9, C_W; clamped as the kernels): C^n, C_T, C_R, C_W, P14's
    C_t, t_v, the rotational mobility β and the P14 weight w_t of the tangential model's arms."""
    c_n = normal_coefficient(p.r_bar, p.mu, p.smin, p.normal_model, p.volume) if p.wet else 0.0
    g = _goldman(6 * math.pi * p.mu * p.r_bar, p.r_bar, p.smin)
    # arms of the rotational terms: r_k, or r_k + S_min/2 for slip (mid-gap point); the largest
    # rotational mobility over S ≤ S_min is at S = S_min (the coefficients are constant below it).
    arm_gap = 0.5 * p.smin if p.tangential_model == 'slip' else 0.0
    sides = [(p.r1, p.m1)] + ([] if p.r2 is None else [(p.r2, p.m2)])
    clamp = _CLAMPED.get(p.tangential_model, lambda c_T, c_R, c_W: (c_T, c_R, c_W, 0.0))
    c_T, c_R, c_W, c_t_net = clamp(g['C_T'], g['C_R'], g['C_W'])
    tangential_on = p.wet and p.tangential_model != 'none'
    return SimpleNamespace(
        c_n=c_n, c_T=c_T, c_R=c_R, c_W=c_W, c_t_net=c_t_net if tangential_on else 0.0, tangential_on=tangential_on,
        t_v=p.m_eff / c_n if c_n > 0 else math.inf,
        beta_rot=p.m_eff * sum(ROT * ((r + arm_gap) / r) ** 2 / m for r, m in sides),  # = 2.5 for r_k arms
        w_rot=1 + ROT * max(((r + arm_gap) / r) ** 2 for r, _ in sides))              # P14 weight, 3.5


def _pair_bounds(p, dry, b):
    """The collision bounds, the viscous pair (P12, explicit only) and the coupled pair (P13)."""
    m, k_n = p.m_eff, dry.k_n
    bounds = [
        Bound('rayleigh', 0.2 * dry.t_r, 'stability',
              '0.2 T_R, T_R = pi r sqrt(rho/G)/(0.1631 nu + 0.876605)', 'collision'),
        Bound('hertz_collision', dry.t_c, 'info', 't_c = 2.868 (m*^2/(rbar E*^2 v))^(1/5)'),
        Bound('elastic_pair', 2 * math.sqrt(m / k_n), 'stability',
              '2 sqrt(m*/k_n), k_n = 2 E* sqrt(rbar delta_max) (P13, C = 0)', 'collision'),
    ]
    if p.explicit and p.wet and b.c_n > 0:
        bounds += [Bound('viscous_pair', 2 * b.t_v, 'stability', '2 t_v = 2 m*/C^n(S_min) (P12)', 'viscous'),
                   Bound('viscous_no_rebound', b.t_v, 'design', 't_v = m*/C^n(S_min) (P12)', 'viscous')]
    cb_n = b.c_n if p.explicit else 0.0  # the bridge dashpot the explicit scheme sees (0 under P15)
    bounds.append(Bound(
        'coupled_pair', pair_limit(m, cb_n + dry.c_n_contact, k_n), 'stability',
        '4m*/(C + sqrt(C^2 + 4 m* k_n)), C = %s%s (P13)' % (
            'C^n(S_min)' if cb_n > 0 else '0 (implicit bridges)' if p.wet and not p.explicit else '0',
            ' + c_n(en)' if dry.c_n_contact > 0 else ''),
        _regime(2 * m / cb_n if cb_n > 0 else math.inf, 2 * math.sqrt(m / k_n))))
    return bounds


def _slip_bounds(m, b):
    return [Bound('tangential_slip', 2 * m / ((1 + b.beta_rot) * b.c_T), 'stability',
                  '2m*/((1+beta) C_T), beta = 2.5(1 + S_min/2r)^2 (~0.571 m*/C_T)', 'viscous')]


def _washino_bounds(m, b):
    bounds = [Bound('tangential_coupled', 2 * m / (b.c_T + ROT * b.c_R), 'stability', '2m*/(C_T + 2.5 C_R) (P13c)',
                    'viscous')]
    if b.c_R > 0:  # C_R > 0 for S_min < 6.6 r̄
        bounds.append(Bound('tangential_rotation', 2 * m / (ROT * b.c_R), 'stability', '0.8 m*/C_R', 'viscous'))
    return bounds


def _goldman_bounds(m, b):
    # u' = -(C_T u + C_R s)/m*, s' = -2.5 (C_R u + C_W s)/m*
    a, bb, c, dd = b.c_T, b.c_R, ROT * b.c_R, ROT * b.c_W
    lam = 0.5 * (a + dd) + math.sqrt(0.25 * (a - dd) ** 2 + bb * c)
    bounds = [Bound('tangential_translation', 2 * m / b.c_T, 'stability', '2m*/C_T', 'viscous')]
    if b.c_W > 0:  # C_W > 0 for S_min < 2.6 r̄
        bounds.append(Bound('tangential_rotation', 2 * m / (ROT * b.c_W), 'stability', '0.8 m*/C_W', 'viscous'))
    bounds.append(Bound('tangential_coupled', 2 * m / lam, 'stability',
                        '2/lambda_max([[C_T, C_R], [2.5 C_R, 2.5 C_W]]/m*)', 'viscous'))
    return bounds


#: The tangential pair bounds of each model (physics.md §3 "Tangential pair"); 'none' has none.
_TANGENTIAL_BOUNDS = {'slip': _slip_bounds, 'washino': _washino_bounds, 'goldman': _goldman_bounds}


def _tangential_bounds(p, b):
    """The tangential pair bounds of the model, explicit only (C_T > 0 for S_min < 6 r̄)."""
    if not (p.explicit and b.tangential_on and b.c_T > 0):
        return []
    return _TANGENTIAL_BOUNDS[p.tangential_model](p.m_eff, b)


def _network_bounds(p, dry, b):
    """The capillary spring (P22) and the network bounds (P14) for z contacts per particle; also
    returns d, κ and k_c for the derived quantities."""
    cb_n = b.c_n if p.explicit else 0.0       # bridge dashpots seen by the explicit scheme (0 under P15)
    cb_t = b.c_t_net if p.explicit else 0.0
    d_bridge = p.z * (cb_n + b.w_rot * cb_t) * p.inv_m
    d = d_bridge + p.z * (dry.c_n_contact + 3.5 * dry.c_s_contact) * p.inv_m
    # the capillary pull, a spring of up to k_c along n (P22), with the stiffnesses of the contact
    k_c = (capillary_max_stiffness(p.capillary_model, p.r_bar, p.gamma, 0.0, p.volume, rupture_distance(p.volume))
           if p.capillary_model != 'none' and p.gamma > 0 else 0.0)
    bounds = []
    if k_c > 0:
        bounds.append(Bound('capillary_spring', 2 * math.sqrt(p.m_eff / k_c), 'stability',
                            '2 sqrt(m*/k_c), k_c = max |dF/dS| of the capillary force (P22)', 'collision'))
    kappa = p.z * (dry.k_n + 3.5 * dry.k_t + k_c) * p.inv_m
    bounds.append(Bound(
        'network', network_limit(d, kappa), 'stability',
        '4/(d + sqrt(d^2 + 4 kappa)), d = z(C_n + %s C_t)(1/m_i+1/m_j), kappa = z(k_n + 3.5 k_t)(1/m_i+1/m_j) (P14)'
        % ('%.4g' % b.w_rot if p.tangential_model == 'slip' else '3.5'),
        _regime(2 / d_bridge if d_bridge > 0 else math.inf, 2 / math.sqrt(kappa))))
    if p.wet and p.explicit and (b.c_n > 0 or b.tangential_on):  # a viscous part the explicit scheme sees
        bounds += [Bound('network_dashpot', 2 / d, 'stability', '2/d (P14, dashpots only)', 'viscous'),
                   Bound('network_no_reversal', 1 / d, 'design', '1/d (P14, no reversal)', 'viscous')]
    return bounds, dict(network_d=d, network_kappa=kappa, k_capillary=k_c)


def _parameters(p):
    """The inputs, after the defaults (S_min, V) were filled in."""
    return dict(radius=p.r1, radius2=p.r2, wall=p.wall,
                density=p.rho, young=p.e, poisson=p.nu, viscosity=p.mu, s_min=p.smin, bridge_volume=p.volume,
                normal_model=p.normal_model, tangential_model=p.tangential_model,
                integration=p.integration, coordination=p.z, impact_velocity=p.v, restitution=p.en,
                capillary_model=p.capillary_model, surface_tension=p.gamma)


def _derived(p, dry, b, network):
    """r̄, m*, E*, G*, δ_max, k_n, k_t, C^n, C_T, C_R, C_W, t_v, d, κ, ... (SI units)."""
    on = b.tangential_on
    return dict(r_bar=p.r_bar, m_eff=p.m_eff, mass1=p.m1, mass2=p.m2, e_star=dry.e_star, g_star=dry.g_star,
                rayleigh_time=dry.t_r, collision_time=dry.t_c, max_overlap=dry.delta, k_n=dry.k_n, k_t=dry.k_t,
                contact_damping_ratio=dry.beta_c, c_n_contact=dry.c_n_contact, c_s_contact=dry.c_s_contact,
                C_n=b.c_n, C_T=b.c_T if on else 0.0, C_R=b.c_R if on else 0.0, C_W=b.c_W if on else 0.0,
                t_v=b.t_v, **network)
