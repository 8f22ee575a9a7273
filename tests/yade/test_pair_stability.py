"""The explicit pair stability limit (physics.md §3): with the gap held below S_min the viscous
coefficient is constant and YADE's leapfrog multiplies the relative normal velocity by
(1 − Δt/t_v) each step, so the pair is stable iff Δt < 2 t_v.  Found here by bisection."""
from yade import O

from wetpairs import R, decay_time_pair, gap_and_approach, head_on_pair

RBAR = R / 2
S_MIN = 1e-3 * RBAR
MU = 1.0


def grows(dt_over_tv, steps=40):
    """Does a tiny relative velocity grow over `steps` steps at Δt = dt_over_tv · t_v?"""
    O.reset()
    # Even at Δt = 3 t_v (×2 per step) the pair moves < 1e-2 S_min in 40 steps, so the gap stays
    # below S_min; near the limit 40 steps separate Δt = 2 t_v ± 0.5 % by a factor 1.5.
    w0 = 1e-15
    head_on_pair(0.5 * S_MIN, w0, viscosity=MU, sMin=S_MIN, tangentialModel='none')
    O.dt = dt_over_tv * decay_time_pair(MU, S_MIN)
    O.run(steps, True)
    assert O.interactions[0, 1].phys.bridge
    return abs(gap_and_approach()[1]) > w0


def test_explicit_pair_limit_is_two_decay_times():
    lo, hi = 1.0, 3.0
    assert not grows(lo) and grows(hi)
    while hi - lo > 0.005:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if grows(mid) else (mid, hi)
    limit = 0.5 * (lo + hi)
    assert abs(limit - 2.0) <= 0.04, 'explicit pair limit %.4f t_v, expected 2 t_v ± 2 %%' % limit
    print('measured explicit pair limit: %.4f t_v' % limit)
