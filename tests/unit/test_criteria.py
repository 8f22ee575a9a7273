"""viscbridge.criteria (viscbridge.planning): the time-step bounds of physics.md §3–§4 (P12–P15),
checked number by number, its argument checks, and its formulas against the C++ kernels' golden
numbers.  Plain Python; the cross-check against YADE's own RayleighWaveTimeStep is in
tests/yade/test_criteria_yade.py."""
import math
import re
import subprocess
import sys

import numpy as np
import pytest

from viscbridge import criteria as C

R, RHO, E, NU = 0.5e-3, 2500.0, 1e7, 0.3   # physics.md "orders of magnitude"
M = RHO * 4.0 / 3.0 * math.pi * R ** 3      # particle mass
GOLDEN = (1 + math.sqrt(5)) / 2


# ---- collision scales -------------------------------------------------------------------------
def test_rayleigh_physics_md_numbers():
    # physics.md §3: 0.2 T_R = 8.7e-6 s at E = 1e7 Pa, 8.7e-7 s at 1e9 Pa (r = 0.5 mm, ρ = 2500)
    dt7 = C.rayleigh_dt(R, RHO, 1e7, NU)
    dt9 = C.rayleigh_dt(R, RHO, 1e9, NU)
    assert dt7 == pytest.approx(8.6543e-6, rel=1e-4)
    assert round(dt7, 7) == pytest.approx(8.7e-6)
    assert round(dt9, 8) == pytest.approx(8.7e-7)
    assert dt7 / dt9 == pytest.approx(math.sqrt(100), rel=1e-12)   # Δt ∝ E^(−1/2)
    assert C.rayleigh_time(R, RHO, 1e7, NU) == pytest.approx(dt7 / 0.2, rel=1e-15)
    assert C.rayleigh_dt(R, RHO, 1e7, NU, fraction=0.5) == pytest.approx(2.5 * dt7, rel=1e-15)


def test_hertz_collision_time_against_integration():
    # integrate m* δ'' = −(4/3) E* √r̄ δ^(3/2) from δ = 0, δ' = v until δ returns to 0
    v = 1.0
    m_eff, r_bar, e_star = M / 2, R / 2, E / (2 * (1 - NU ** 2))
    kno = 4.0 / 3.0 * e_star * math.sqrt(r_bar)
    tc = C.hertz_collision_time(R, R, RHO, E, NU, v)
    dt = tc / 200000
    x, u, t = 0.0, v, 0.0
    while True:
        u -= dt * kno * max(x, 0.0) ** 1.5 / m_eff
        x += dt * u
        t += dt
        if x < 0:
            break
    assert tc == pytest.approx(t, rel=2e-4)
    # the maximum overlap of the same collision, and the closed form 2.868 (m*²/(r̄E*²v))^(1/5)
    assert C.hertz_max_overlap(m_eff, r_bar, e_star, v) == pytest.approx(
        (15 * m_eff * v ** 2 / (16 * e_star * math.sqrt(r_bar))) ** 0.4, rel=1e-15)
    assert tc == pytest.approx(2.868 * (m_eff ** 2 / (r_bar * e_star ** 2 * v)) ** 0.2, rel=1e-15)
    assert tc == pytest.approx(1.0195e-4, rel=1e-4)
    # wall: r̄ = r, m* = m
    assert C.hertz_collision_time(R, None, RHO, E, NU, v, wall=True) == pytest.approx(
        2.868 * (M ** 2 / (R * e_star ** 2 * v)) ** 0.2, rel=1e-15)


def test_moduli_as_yade_mindlin():
    # HertzMindlin.hpp: E* = E1E2/((1−ν1²)E2 + (1−ν2²)E1), G* = 1/((2−ν1)/G1 + (2−ν2)/G2)
    assert C.effective_young(E, NU) == pytest.approx(E / (2 * (1 - NU ** 2)), rel=1e-15)
    G = E / (2 * (1 + NU))
    assert C.effective_shear(E, NU) == pytest.approx(G / (2 * (2 - NU)), rel=1e-15)
    assert C.effective_young(3.1e7, 0.27, 4.7e8, 0.19) == pytest.approx(
        1 / ((1 - 0.27 ** 2) / 3.1e7 + (1 - 0.19 ** 2) / 4.7e8), rel=1e-14)
    # tangent stiffnesses: k_n = 3/2 kno δ^½ with kno = 4/3 E*√r̄; k_s = kso δ^½ with kso = 8√r̄ G*
    d, rb = 1e-6, R / 2
    assert C.hertz_normal_stiffness(rb, 1.0, d) == pytest.approx(1.5 * 4 / 3 * math.sqrt(rb) * math.sqrt(d))
    assert C.mindlin_tangential_stiffness(rb, 1.0, d) == pytest.approx(8 * math.sqrt(rb) * math.sqrt(d))


def test_restitution_damping_ratio_values():
    assert C.restitution_damping_ratio(1.0) == 0.0
    # Thornton et al. 2013 polynomial; en → β (ζ of a linear oscillator would give 0.2155 at 0.5)
    beta = C.restitution_damping_ratio(0.5)
    assert 0.15 < beta < 0.3
    assert C.restitution_damping_ratio(0.2) > beta > C.restitution_damping_ratio(0.8)


# ---- viscous decay time (P12) -----------------------------------------------------------------
def test_tv_identities():
    mu, s = 0.37, 2.3e-7
    assert C.viscous_decay_time(R, RHO, mu, s) == pytest.approx(4 / 9 * RHO * R * s / mu, rel=1e-14)
    assert C.viscous_decay_time(R, RHO, mu, s, wall=True) == pytest.approx(2 / 9 * RHO * R * s / mu, rel=1e-14)
    # general m* S/(6πμ r̄²) for unequal spheres
    r2 = 0.8e-3
    m2 = RHO * 4 / 3 * math.pi * r2 ** 3
    rb, ms = R * r2 / (R + r2), M * m2 / (M + m2)
    assert C.viscous_decay_time(R, RHO, mu, s, radius2=r2) == pytest.approx(ms * s / (6 * math.pi * mu * rb ** 2), rel=1e-14)
    # physics.md §5: A = 6πμ r̄²/m* = 1.8 μ (pair), 3.6 μ (wall), so t_v = S_min/A
    assert C.viscous_decay_time(R, RHO, 1.0, 1.0) == pytest.approx(1 / 1.8, rel=1e-14)
    assert C.viscous_decay_time(R, RHO, 1.0, 1.0, wall=True) == pytest.approx(1 / 3.6, rel=1e-14)
    assert C.viscous_decay_time(R, RHO, 0.0, s) == math.inf
    assert C.viscous_decay_time(R, RHO, 1.0, s, normal_model='none') == math.inf


def test_pair_limit_orders_of_magnitude():
    # physics.md: 2 t_v = 5.6e-7 s at μ = 1 Pa·s, S_min = 1e-3 r — r is the PARTICLE radius there
    # (S_min = 2e-3 r̄); with S_min = 1e-3 r̄ (the sMinRel default) the limit is half of it.
    two_tv_r = 2 * C.viscous_decay_time(R, RHO, 1.0, 1e-3 * R)
    assert two_tv_r == pytest.approx(5.5556e-7, rel=1e-4)
    assert round(two_tv_r, 8) == pytest.approx(5.6e-7)
    crit = C.critical_dt(R, RHO, E, NU, 1.0)                          # default S_min = 1e-3 r̄
    assert crit.parameters['s_min'] == pytest.approx(1e-3 * R / 2)
    assert crit.bound('viscous_pair').value == pytest.approx(two_tv_r / 2, rel=1e-14)
    assert C.critical_dt(R, RHO, E, NU, 1.0, s_min=1e-3 * R).bound('viscous_pair').value == pytest.approx(two_tv_r, rel=1e-14)
    # "scaling as S_min/μ"
    assert 2 * C.viscous_decay_time(R, RHO, 10.0, 1e-2 * R) == pytest.approx(two_tv_r, rel=1e-14)
    # "At μ = 1000 Pa·s, S_min = 1e-5 r the viscous step is 3e6 times smaller than the Hertz one":
    # 2 t_v gives 1.6e6 with S_min = 1e-5 r, 3.1e6 with S_min = 1e-5 r̄ (or with t_v itself)
    hertz = C.rayleigh_dt(R, RHO, 1e7, NU)
    assert hertz / (2 * C.viscous_decay_time(R, RHO, 1000.0, 1e-5 * R)) == pytest.approx(1.558e6, rel=1e-3)
    assert hertz / (2 * C.viscous_decay_time(R, RHO, 1000.0, 1e-5 * R / 2)) == pytest.approx(3.115e6, rel=1e-3)


def test_pitois_decay_time():
    s, V = 1e-3 * R / 2, 0.01 * 4 / 3 * math.pi * R ** 3
    x = V / (math.pi * (R / 2) * s * s)
    factor = (1 - (1 + x) ** -0.5) ** 2
    t_ap = C.viscous_decay_time(R, RHO, 1.0, s)
    assert C.viscous_decay_time(R, RHO, 1.0, s, normal_model='pitois', bridge_volume=V) == pytest.approx(t_ap / factor, rel=1e-12)
    assert C.pitois_volume_factor(R / 2, s, V) == pytest.approx(0.99390, rel=1e-4)
    # the default V = 1 % of the particle volume is used by critical_dt
    crit = C.critical_dt(R, RHO, E, NU, 1.0, normal_model='pitois')
    assert crit.parameters['bridge_volume'] == pytest.approx(V, rel=1e-14)
    assert crit.derived['t_v'] == pytest.approx(t_ap / factor, rel=1e-12)


def test_tangential_coefficients():
    mu, s = 2.0, 1e-3 * R / 2
    c = C.tangential_coefficients(R, mu, s)
    f, L = 6 * math.pi * mu * R / 2, math.log(1000.0)
    assert c['C_T'] == pytest.approx(f * (8 / 15 * L + 0.9588), rel=1e-14)
    assert c['C_R'] == pytest.approx(f * (2 / 15 * L + 0.2526), rel=1e-14)   # + sign (physics.md §2)
    assert c['C_W'] == pytest.approx(f * (8 / 15 * L + 0.5089), rel=1e-14)
    w = C.tangential_coefficients(R, mu, s, wall=True)
    assert w['C_T'] == pytest.approx(6 * math.pi * mu * R * (8 / 15 * math.log(R / s) + 0.9588), rel=1e-14)


# ---- P13 ---------------------------------------------------------------------------------------
def test_p13_limits_and_golden_ratio():
    m, k, c = 2.0e-6, 3.0e3, 1.0e-2
    assert C.pair_limit(m, c, 0.0) == pytest.approx(2 * m / c, rel=1e-15)             # 2 t_v
    assert C.pair_limit(m, c, 1e-12 * c * c / m) == pytest.approx(2 * m / c, rel=1e-9)  # k → 0
    assert C.pair_limit(m, 0.0, k) == pytest.approx(2 * math.sqrt(m / k), rel=1e-15)
    assert C.pair_limit(m, 1e-9 * math.sqrt(m * k), k) == pytest.approx(2 * math.sqrt(m / k), rel=1e-8)
    # damping ratio ζ = C/(2√(m*k)) = 0.5: min(elastic, viscous) overestimates P13 by 1.618
    c_half = 0.5 * 2 * math.sqrt(m * k)
    naive = min(2 * math.sqrt(m / k), 2 * m / c_half)
    assert naive / C.pair_limit(m, c_half, k) == pytest.approx(GOLDEN, rel=1e-12)
    assert round(naive / C.pair_limit(m, c_half, k), 3) == 1.618
    # R5: ω₀Δt = 2(√(1+ζ²) − ζ) for every ζ, and 1.618 is the largest optimism
    ratios = []
    for zeta in np.linspace(0.01, 5, 500):
        cz = 2 * zeta * math.sqrt(m * k)
        dt = C.pair_limit(m, cz, k)
        assert math.sqrt(k / m) * dt == pytest.approx(2 * (math.sqrt(1 + zeta ** 2) - zeta), rel=1e-12)
        ratios.append(min(2 * math.sqrt(m / k), 2 * m / cz) / dt)
    assert max(ratios) == pytest.approx(GOLDEN, rel=1e-4)


def _leapfrog_grows(m, c, k, dt, steps=4000):
    """Linear spring-dashpot under YADE's leapfrog (force from v_{n−1/2}); True if it diverges
    (a stable run near the limit stays within a few times its initial amplitude)."""
    x, v = 1.0, 0.0
    for _ in range(steps):
        v += dt * (-k * x - c * v) / m
        x += dt * v
        if abs(x) > 1e3:
            return True
    return False


@pytest.mark.parametrize('zeta', [0.0, 0.2, 0.5, 2.0, 20.0])
def test_p13_is_the_leapfrog_threshold(zeta):
    m, k = 1.0, 1.0
    c = 2 * zeta * math.sqrt(m * k)
    dt = C.pair_limit(m, c, k)
    assert not _leapfrog_grows(m, c, k, 0.99 * dt)
    assert _leapfrog_grows(m, c, k, 1.01 * dt)


# ---- P14 ---------------------------------------------------------------------------------------
def test_p14_pieces_equal_pair_limit():
    mu, s = 1.0, 1e-3 * R / 2
    tv = C.viscous_decay_time(R, RHO, mu, s)
    cn = C.normal_coefficient(R / 2, mu, s)
    d = 1 * (cn + 3.5 * 0.0) * (1 / M + 1 / M)     # z = 1, C_t = 0
    assert C.network_limit(d, 0.0) == pytest.approx(2 * tv, rel=1e-14)
    assert C.network_limit(0.0, 4.0) == pytest.approx(1.0, rel=1e-15)   # 2/√κ
    # with springs, P14 with z = 1 is P13 of the pair
    k = 7.0
    assert C.network_limit(d, k * 2 / M) == pytest.approx(C.pair_limit(M / 2, cn, k), rel=1e-13)
    # and inside critical_dt (tangential 'none', z = 1): the dashpot part is exactly 2 t_v
    crit = C.critical_dt(R, RHO, E, NU, mu, tangential_model='none')
    assert crit.bound('network_dashpot').value == pytest.approx(2 * tv, rel=1e-14)
    assert crit.bound('network_no_reversal').value == pytest.approx(tv, rel=1e-14)
    assert crit.bound('viscous_pair').value == pytest.approx(2 * tv, rel=1e-14)
    k_n, k_t = crit.derived['k_n'], crit.derived['k_t']
    assert crit.bound('network').value == pytest.approx(
        C.network_limit(cn * 2 / M, (k_n + 3.5 * k_t) * 2 / M), rel=1e-14)


def test_p14_coordination_scaling():
    # dashpots only: Δt ∝ 1/z; the wall counts one mass (1/m_j = 0)
    c1 = C.critical_dt(R, RHO, E, NU, 1.0, coordination=1)
    c6 = C.critical_dt(R, RHO, E, NU, 1.0, coordination=6)
    assert c6.bound('network_dashpot').value == pytest.approx(c1.bound('network_dashpot').value / 6, rel=1e-14)
    w = C.critical_dt(R, RHO, E, NU, 1.0, wall=True, tangential_model='none')
    tv = C.viscous_decay_time(R, RHO, 1.0, 1e-3 * R, wall=True)
    assert w.bound('network_dashpot').value == pytest.approx(2 * tv, rel=1e-14)


def test_planning_stays_with_p14_because_a_random_bed_is_below_the_lattice_limit():
    """The study's wetted random bed (μ = 1 Pa·s, equal spheres, z = 4.5) blew up above a step below
    the simple cubic lattice's limit, although it has fewer contacts: its top mode is local.  So the
    lattice limit is no planning value, and critical_dt's P14 stays below the measurement even with
    z rounded up to 6."""
    import csv
    import os
    data = os.path.join(os.path.dirname(__file__), '..', '..', 'docs', 'data', 'critical_dt_explicit.csv')
    base = [r for r in csv.DictReader(open(data)) if r['viscosity'] == '1.0' and r['sMinRel'] == '0.001'
            and r['sizeRatio'] == '1.0' and r['normalModel'] == 'adamsPerchard' and r['radius'] == '0.0005']
    measured = float(base[0]['dt_critical'])
    plan = C.critical_dt(R, RHO, E, NU, 1.0, coordination=6)
    lattice = C.lattice_limit(R, RHO, 1.0, 6, s_min=plan.parameters['s_min'], spring=plan.derived['k_n'],
                              tangential_spring=plan.derived['k_t'])['h']
    assert lattice > 1.3 * measured
    for z in (4, 5, 6):
        assert C.critical_dt(R, RHO, E, NU, 1.0, coordination=z).stability_limit < measured


def test_lattice_limit_without_dashpots_or_springs_is_unbounded():
    assert C.lattice_limit(R, RHO, 0.0, 6)['h'] == math.inf

def _damping_system(radii, positions, contacts, model, s_min, mu=1.0):
    """Generalised damping matrix M⁻¹D of the bridges of a cluster (6 dof per sphere), built from
    the force laws of TangentialViscous.hpp / NormalViscous.hpp linearised at fixed geometry."""
    nb = len(radii)
    mass = RHO * 4 / 3 * math.pi * np.asarray(radii) ** 3
    Mdiag = np.concatenate([[m] * 3 + [0.4 * m * r * r] * 3 for m, r in zip(mass, radii)])
    D = np.zeros((6 * nb, 6 * nb))
    for i, j in contacts:
        n = positions[j] - positions[i]
        n = n / np.linalg.norm(n)
        rb = radii[i] * radii[j] / (radii[i] + radii[j])
        cn = C.normal_coefficient(rb, mu, s_min)
        g = C.tangential_coefficients(radii[i], mu, s_min, radius2=radii[j])
        N = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
        Pt = np.eye(3) - np.outer(n, n)
        arm = 0.5 * s_min if model == 'slip' else 0.0
        Bn, Bu, Bs = np.zeros((1, 6 * nb)), np.zeros((3, 6 * nb)), np.zeros((3, 6 * nb))
        Bn[0, 6 * i:6 * i + 3], Bn[0, 6 * j:6 * j + 3] = n, -n
        Bu[:, 6 * i:6 * i + 3], Bu[:, 6 * j:6 * j + 3] = Pt, -Pt
        Bs[:, 6 * i + 3:6 * i + 6] = -N * (radii[i] + arm)
        Bs[:, 6 * j + 3:6 * j + 6] = -N * (radii[j] + arm)
        D += cn * Bn.T @ Bn
        if model == 'slip':
            D += g['C_T'] * (Bu + Bs).T @ (Bu + Bs)
        elif model == 'washino':
            D += (Bu + Bs).T @ (g['C_T'] * Bu + g['C_R'] * Bs)
        elif model == 'goldman':
            D += Bu.T @ (g['C_T'] * Bu + g['C_R'] * Bs) + Bs.T @ (g['C_R'] * Bu + g['C_W'] * Bs)
    return D / Mdiag[:, None]


def _explicit_limit(A):
    """Largest Δt with |1 − Δt λ| < 1 for every nonzero eigenvalue λ of A."""
    lam = np.linalg.eigvals(A)
    lam = lam[np.abs(lam) > 1e-9 * np.abs(lam).max()]
    assert np.all(lam.real > 0)
    return float(np.min(2 * lam.real / np.abs(lam) ** 2))


@pytest.mark.parametrize('model', ['none', 'slip', 'washino', 'goldman'])
@pytest.mark.parametrize('s_rel', [1e-3, 0.1, 1.0])
def test_pair_bounds_against_the_full_pair_spectrum(model, s_rel):
    """The pair bounds of the normal and tangential terms are the exact explicit limits of an
    equal pair (12 dof), and P14 (z = 1) is below them."""
    s_min = s_rel * R / 2
    A = _damping_system([R, R], np.array([[0, 0, 0], [2 * R, 0, 0.]]), [(0, 1)], model, s_min)
    exact = _explicit_limit(A)
    crit = C.critical_dt(R, RHO, E, NU, 1.0, s_min=s_min, tangential_model=model)
    pair = min(b.value for b in crit.bounds if b.name in ('viscous_pair',) or b.name.startswith('tangential_'))
    assert pair == pytest.approx(exact, rel=1e-9)
    assert crit.bound('network_dashpot').value <= exact * (1 + 1e-12)


@pytest.mark.parametrize('model', ['slip', 'washino', 'goldman'])
def test_p14_is_sufficient_on_random_clusters(model):
    rng = np.random.default_rng(7)
    for _ in range(8):
        nb = int(rng.integers(4, 14))
        radii = rng.uniform(0.3e-3, 0.7e-3, nb)
        pos = rng.uniform(0, nb ** (1 / 3) * 1.1e-3, (nb, 3))
        contacts = [(i, j) for i in range(nb) for j in range(i + 1, nb)
                    if np.linalg.norm(pos[i] - pos[j]) < 1.3 * (radii[i] + radii[j])]
        if not contacts:
            continue
        for s_rel in (1e-3, 0.3):
            A = _damping_system(radii, pos, contacts, model, s_rel * 0.15e-3)
            exact = _explicit_limit(A)
            # P14 with the per-particle sums, each contact evaluated with its own r̄, m*
            d = np.zeros(nb)
            for i, j in contacts:
                c = C.critical_dt(radii[i], RHO, E, NU, 1.0, radius2=radii[j], s_min=s_rel * 0.15e-3,
                                  tangential_model=model)
                w = c.derived['network_d']        # z = 1: (C_n + w_t C_t)(1/m_i + 1/m_j)
                d[i] += w
                d[j] += w
            assert 2 / d.max() <= exact * (1 + 1e-9)


def test_goldman_tangential_pair_needs_the_coupled_bound():
    # physics.md P13c: for `goldman` the rotation resistance is C_W, and the exact coupled limit
    # 2/λ_max is ~2.4× below 2m*/C_T at S = 1e-3 r̄: check it by integration.
    s_min = 1e-3 * R / 2
    crit = C.critical_dt(R, RHO, E, NU, 1.0, tangential_model='goldman', normal_model='none')
    g = C.tangential_coefficients(R, 1.0, s_min)
    ms = M / 2
    A = np.array([[g['C_T'], g['C_R']], [2.5 * g['C_R'], 2.5 * g['C_W']]]) / ms
    exact = crit.bound('tangential_coupled').value
    assert exact == pytest.approx(2 / max(np.linalg.eigvals(A).real), rel=1e-12)
    assert 2 * ms / g['C_T'] / exact == pytest.approx(2.374, rel=1e-3)
    assert 0.8 * ms / g['C_R'] / exact > 3

    def grows(dt):
        w = np.array([1.0, 0.3])
        for _ in range(3000):
            w = w - dt * A @ w
            if np.abs(w).max() > 1e3:
                return True
        return False
    assert not grows(0.99 * exact) and grows(1.01 * exact)
    assert grows(0.9 * 2 * ms / g['C_T'])
    tangential = [b.value for b in crit.bounds if b.name.startswith('tangential_')]
    assert min(tangential) == exact
    # P14's 3.5 C_T (Gershgorin-type) stays below the exact pair limit
    assert crit.bound('network_dashpot').value < exact


# ---- critical_dt as a whole --------------------------------------------------------------------
def test_worked_example():
    crit = C.critical_dt(R, RHO, E, NU, 1.0)
    v = {b.name: b.value for b in crit.bounds}
    assert v['rayleigh'] == pytest.approx(8.654e-6, rel=1e-3)
    assert v['hertz_collision'] == pytest.approx(1.019e-4, rel=1e-3)
    assert v['elastic_pair'] == pytest.approx(5.060e-5, rel=1e-3)
    assert v['viscous_pair'] == pytest.approx(2.778e-7, rel=1e-3)
    assert v['viscous_no_rebound'] == pytest.approx(1.389e-7, rel=1e-3)
    assert v['coupled_pair'] == pytest.approx(2.778e-7, rel=1e-3)
    assert v['tangential_slip'] == pytest.approx(1.709e-5, rel=1e-3)
    assert v['tangential_slip'] == pytest.approx(0.571 * (M / 2) / crit.derived['C_T'], rel=1e-3)
    assert v['network'] == pytest.approx(2.733e-7, rel=1e-3)
    assert crit.stability_limit == v['network']
    assert crit.governing == 'network' and crit.regime == 'viscous'
    assert crit.no_rebound_limit == pytest.approx(1.367e-7, rel=1e-3)
    assert crit.bound('hertz_collision').kind == 'info'
    text = str(crit)
    for name in v:
        assert name in text
    d = crit.as_dict()
    assert d['stability_limit'] == crit.stability_limit and len(d['bounds']) == len(crit.bounds)


def test_dry_has_no_viscous_bound():
    crit = C.critical_dt(R, RHO, E, NU, 0.0)
    assert crit.names() == ['rayleigh', 'hertz_collision', 'elastic_pair', 'coupled_pair', 'network']
    assert crit.governing == 'rayleigh' and crit.regime == 'collision'
    assert crit.bound('coupled_pair').value == pytest.approx(crit.bound('elastic_pair').value, rel=1e-14)
    assert crit.stability_limit == pytest.approx(8.654e-6, rel=1e-3)


def test_implicit_drops_viscous_bounds():
    crit = C.critical_dt(R, RHO, E, NU, 1000.0, integration='implicit', tangential_model='washino')
    assert crit.regime == 'collision'
    assert crit.governing == 'rayleigh'
    assert all(b.regime != 'viscous' for b in crit.bounds)
    assert not any(b.name.startswith(('viscous', 'tangential', 'network_')) for b in crit.bounds)
    assert crit.bound('coupled_pair').value == pytest.approx(crit.bound('elastic_pair').value, rel=1e-14)
    dry = C.critical_dt(R, RHO, E, NU, 0.0)
    assert crit.stability_limit == dry.stability_limit
    assert crit.bound('network').value == pytest.approx(dry.bound('network').value, rel=1e-14)
    explicit = C.critical_dt(R, RHO, E, NU, 1000.0)
    assert explicit.regime == 'viscous'
    assert crit.stability_limit / explicit.stability_limit > 3e4


def test_regime_switches_once_and_limit_is_monotone():
    mus = np.logspace(-3, 3, 61)
    res = [C.critical_dt(R, RHO, E, NU, mu) for mu in mus]
    limits = [c.stability_limit for c in res]
    assert all(b <= a for a, b in zip(limits, limits[1:]))
    regimes = [c.regime for c in res]
    assert regimes[0] == 'collision' and res[0].governing == 'rayleigh'
    assert regimes[-1] == 'viscous' and res[-1].governing == 'network'
    switches = sum(1 for a, b in zip(regimes, regimes[1:]) if a != b)
    assert switches == 1
    # the switch happens where 2/d = 0.2 T_R: μ ≈ 0.032 Pa·s here
    first = mus[regimes.index('viscous')]
    assert 0.02 < first < 0.05
    # the no-rebound limit is never above the stability limit
    assert all(c.no_rebound_limit <= c.stability_limit for c in res)


def test_unequal_pair_and_wall_geometry():
    r2 = 1.0e-3
    crit = C.critical_dt(R, RHO, E, NU, 1.0, radius2=r2)
    assert crit.derived['r_bar'] == pytest.approx(R * r2 / (R + r2))
    m2 = RHO * 4 / 3 * math.pi * r2 ** 3
    assert crit.derived['m_eff'] == pytest.approx(M * m2 / (M + m2))
    assert crit.bound('rayleigh').value == pytest.approx(C.rayleigh_dt(R, RHO, E, NU))   # smaller sphere
    assert crit.parameters['bridge_volume'] == pytest.approx(0.01 * 0.5 * 4 / 3 * math.pi * (R ** 3 + r2 ** 3))
    w = C.critical_dt(R, RHO, E, NU, 1.0, wall=True)
    assert w.derived['r_bar'] == R and w.derived['m_eff'] == pytest.approx(M)
    assert w.parameters['s_min'] == pytest.approx(1e-3 * R)
    assert w.parameters['bridge_volume'] == pytest.approx(0.01 * 4 / 3 * math.pi * R ** 3)


def test_slip_arm_factor():
    # slip torques act at r + S/2: the rotational mobility grows to 2.5(1 + S_min/2r)²
    s_min = R / 2                                           # S_min = r̄
    crit = C.critical_dt(R, RHO, E, NU, 1.0, s_min=s_min, normal_model='none')
    ct = crit.derived['C_T']
    beta = 2.5 * (1 + s_min / (2 * R)) ** 2
    assert crit.bound('tangential_slip').value == pytest.approx(2 * (M / 2) / ((1 + beta) * ct), rel=1e-14)
    assert crit.bound('network_dashpot').value == pytest.approx(2 / ((1 + beta) * ct * 2 / M), rel=1e-14)


def test_contact_damping_enters_p13_and_p14():
    e = 0.5
    crit = C.critical_dt(R, RHO, E, NU, 0.0, restitution=e)
    beta = C.restitution_damping_ratio(e)
    ms, kn = M / 2, crit.derived['k_n']
    assert crit.bound('coupled_pair').value == pytest.approx(C.pair_limit(ms, 2 * beta * math.sqrt(ms * kn), kn), rel=1e-14)
    assert crit.bound('coupled_pair').value < crit.bound('elastic_pair').value


def test_module_does_not_import_yade():
    code = ("import sys; import viscbridge.criteria as c; "
            "c.critical_dt(0.5e-3, 2500, 1e7, 0.3, 1.0); print('yade' in sys.modules)")
    env_path = [p for p in sys.path if p]
    out = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                         env={'PYTHONPATH': ':'.join(env_path), 'PATH': '/usr/bin:/bin'}, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == 'False'


# ---- validation --------------------------------------------------------------------------------
BAD = [
    (dict(radius=0), 'radius', '0'),
    (dict(radius=-1e-3), 'radius', '-0.001'),
    (dict(radius2=-1.0), 'radius2', '-1.0'),
    (dict(wall=True, radius2=1e-3), 'radius2', '0.001'),
    (dict(density=0), 'density', '0'),
    (dict(young=-5.0), 'young', '-5.0'),
    (dict(young=float('nan')), 'young', 'nan'),
    (dict(poisson=0.5), 'poisson', '0.5'),
    (dict(poisson=-1.0), 'poisson', '-1.0'),
    (dict(viscosity=-1e-3), 'viscosity', '-0.001'),
    (dict(s_min=0.0), 's_min', '0.0'),
    (dict(s_min=-1e-9), 's_min', '-1e-09'),
    (dict(s_min_rel=0.0), 's_min_rel', '0.0'),
    (dict(s_min_rel=2.0), 's_min_rel', '2.0'),
    (dict(bridge_volume=0.0), 'bridge_volume', '0.0'),
    (dict(bridge_volume_rel=1.5), 'bridge_volume_rel', '1.5'),
    (dict(normal_model='stokes'), 'normal_model', 'stokes'),
    (dict(tangential_model='Slip'), 'tangential_model', 'Slip'),
    (dict(integration='rk4'), 'integration', 'rk4'),
    (dict(coordination=0), 'coordination', '0'),
    (dict(coordination=0.5), 'coordination', '0.5'),
    (dict(impact_velocity=0.0), 'impact_velocity', '0.0'),
    (dict(restitution=0.0), 'restitution', '0.0'),
    (dict(restitution=1.2), 'restitution', '1.2'),
    (dict(young='stiff'), 'young', 'stiff'),
]


@pytest.mark.parametrize('change,name,value', BAD)
def test_critical_dt_rejects(change, name, value):
    kw = dict(radius=R, density=RHO, young=E, poisson=NU, viscosity=1.0)
    kw.update(change)
    args = [kw.pop(k) for k in ('radius', 'density', 'young', 'poisson', 'viscosity')]
    with pytest.raises(ValueError) as err:
        C.critical_dt(*args, **kw)
    msg = str(err.value)
    assert name + '=' in msg and value in msg and 'allowed' in msg


def test_other_functions_reject():
    with pytest.raises(ValueError, match=r'poisson=0\.7 .*\(-1, 0\.5\)'):
        C.rayleigh_time(R, RHO, E, 0.7)
    with pytest.raises(ValueError, match='fraction=0'):
        C.rayleigh_dt(R, RHO, E, NU, fraction=0)
    with pytest.raises(ValueError, match='impact_velocity=-1'):
        C.hertz_collision_time(R, R, RHO, E, NU, -1)
    with pytest.raises(ValueError, match="bridge_volume=None .*pitois"):
        C.viscous_decay_time(R, RHO, 1.0, 1e-7, normal_model='pitois')
    with pytest.raises(ValueError, match='s_min=0'):
        C.viscous_decay_time(R, RHO, 1.0, 0)
    with pytest.raises(ValueError, match='viscosity=-2'):
        C.tangential_coefficients(R, -2, 1e-7)
    with pytest.raises(ValueError, match='s=0'):
        C.tangential_coefficients(R, 1.0, 0)


@pytest.mark.parametrize('args,kw,name', [
    ((0.5e-3, 2500, 1e7, 0.3, '1'), {}, 'viscosity'), ((0.5e-3, 2500, 1e7, 0.3, True), {}, 'viscosity'),
    (('0.5e-3', 2500, 1e7, 0.3, 1.0), {}, 'radius'), ((0.5e-3, 2500, 1e7, 0.3, 1.0), dict(coordination='6'), 'coordination'),
])
def test_criteria_wrong_types_name_the_parameter(args, kw, name):
    with pytest.raises(ValueError, match=name):
        C.critical_dt(*args, **kw)


@pytest.mark.parametrize('kw,message', [
    (dict(s_min_rel=-1), 's_min_rel=-1 is out of range'), (dict(s_min_rel=5), 's_min_rel=5 is out of range'),
    (dict(spring=-5), 'spring=-5 is out of range'), (dict(spring='a'), "spring='a' is out of range"),
    (dict(q_points=0), 'q_points=0 is out of range'), (dict(q_points=2.5), 'q_points=2.5 is out of range'),
    (dict(normal_model='pitois', bridge_volume=-1), 'bridge_volume=-1 is out of range'),
])
def test_lattice_limit_wrong_values_name_the_parameter(kw, message):
    with pytest.raises(ValueError, match=re.escape('lattice_limit: ' + message)):
        C.lattice_limit(0.5e-3, 2500, 1.0, 6, **kw)


@pytest.mark.parametrize('args,message', [
    ((2.5e-4, 1.0, 1e-7, 'x'), "normal_model='x' is not a known name"), ((2.5e-4, 1.0, 0.0), 'gap=0.0 is out of range'),
])
def test_normal_coefficient_refuses_an_unknown_model_and_a_zero_gap(args, message):
    """It returned the Adams–Perchard value for any unknown name, and divided by zero at S = 0."""
    with pytest.raises(ValueError, match=re.escape('normal_coefficient: ' + message)):
        C.normal_coefficient(*args)


# --- one formula source: the C++ kernels' numbers on a grid, against viscbridge.criteria ---------
def _golden():
    import json
    import os
    import subprocess
    tool = os.environ.get('VISCBRIDGE_REGISTRY_TOOL', os.path.join(os.environ.get('VISCBRIDGE_BUILD', 'build'), 'viscbridge_registry'))
    out = subprocess.run([tool, '--golden'], capture_output=True, text=True, check=True).stdout
    return [json.loads(line) for line in out.splitlines()]


def _r_bar(i):
    return C.reduced_radius(i['r1'], i['r2'] or None)


def _hertz(i, which):
    R = i['R1'] * i['R2'] / (i['R1'] + i['R2'])
    if which == 'kno':
        return 4.0 / 3.0 * C.effective_young(i['E1'], i['nu1'], i['E2'], i['nu2']) * math.sqrt(R)
    return 8 * math.sqrt(R) * C.effective_shear(i['E1'], i['nu1'], i['E2'], i['nu2'])


PYTHON_OF = {
    'adamsPerchard': lambda i: C.normal_coefficient(_r_bar(i), i['mu'], i['S'], 'adamsPerchard'),
    'pitois': lambda i: C.normal_coefficient(_r_bar(i), i['mu'], i['S'], 'pitois', i['V']),
    'pitoisFactor': lambda i: C.pitois_volume_factor(_r_bar(i), i['S'], i['V']),
    'C_T': lambda i: C.tangential_coefficients(i['r1'], i['mu'], i['S'], i['r2'] or None, wall=not i['r2'])['C_T'],
    'C_R': lambda i: C.tangential_coefficients(i['r1'], i['mu'], i['S'], i['r2'] or None, wall=not i['r2'])['C_R'],
    'C_W': lambda i: C.tangential_coefficients(i['r1'], i['mu'], i['S'], i['r2'] or None, wall=not i['r2'])['C_W'],
    'viscousStepCoefficient': lambda i: C.viscous_step_coefficient(i['r1'], i['r2'] or None, 1.0, i['sMin'], i['normal'],
                                                                          i['tangential'], i['V']),
    'capillaryForce': lambda i: C.capillary_force(i['model'], _r_bar(i), i['gamma'], i['theta'], i['V'], i['S']),
    'capillaryStiffness': lambda i: C.capillary_stiffness(i['model'], _r_bar(i), i['gamma'], i['theta'], i['V'], i['S']),
    'capillaryMaxStiffness': lambda i: C.capillary_max_stiffness(i['model'], _r_bar(i), i['gamma'], i['theta'], i['V'],
                                                                        i['sRup']),
    'dampingRatio': lambda i: C.restitution_damping_ratio(i['e']),
    'rayleighTime': lambda i: C.rayleigh_time(i['r'], i['rho'], i['E'], i['nu']),
    'kno': lambda i: _hertz(i, 'kno'),
    'kso': lambda i: _hertz(i, 'kso'),
    'networkLimit': lambda i: C.network_limit(i['d'], i['kappa']),
    'ruptureDistance': lambda i: C.rupture_distance(i['V'], i['theta']),
}


def test_criteria_reproduce_the_kernels_to_1e_12():
    rows = _golden()
    assert {r['q'] for r in rows} == set(PYTHON_OF), 'a quantity without its Python counterpart (or the reverse)'
    worst = {}
    for r in rows:
        ours = PYTHON_OF[r['q']](r['in'])
        ref = r['v']
        err = 0.0 if ours == ref else abs(ours - ref) / max(abs(ref), 1e-300)
        worst[r['q']] = max(worst.get(r['q'], 0.0), err)
    assert all(e <= 1e-12 for e in worst.values()), {k: v for k, v in worst.items() if v > 1e-12}
    assert len(rows) > 2000


@pytest.mark.parametrize('call, name', [
    (lambda: C.rupture_distance(-1), 'bridge_volume'),
    (lambda: C.rupture_distance(1e-12, contact_angle=2.0), 'contact_angle'),
    (lambda: C.pair_limit(1e-6, damping=-1, stiffness=0), 'damping'),
    (lambda: C.pair_limit(0, damping=1, stiffness=0), 'm_eff'),
    (lambda: C.pair_limit(1e-6, damping=1, stiffness=float('nan')), 'stiffness'),
    (lambda: C.network_limit(-1, 0), 'd'),
    (lambda: C.rayleigh_dt(0.5e-3, 2500, 1e7, 0.3, fraction=2), 'fraction'),
])
def test_helpers_refuse_out_of_range_values_by_name(call, name):
    with pytest.raises(ValueError, match=name):
        call()
