"""Bisection of the threshold of a monotone stable→unstable predicate, in log space: how a scan
brackets a case's critical time step.  Plain Python.
"""
import math

__all__ = ['bisect_threshold']


def bisect_threshold(is_unstable, lo, hi, tolerance=0.02, max_expand=30):
    """Bracket the smallest unstable value of a monotone stable→unstable predicate, in log space.

    Starts from a guess [lo, hi]; moves lo down (÷2) until stable and hi up (×2) until unstable,
    then bisects until hi/lo ≤ 1 + tolerance.  Returns (lo, hi, trials) with `trials` the list of
    (value, unstable) evaluated, in order.
    """
    if not (0 < lo < hi):
        raise ValueError('bisect_threshold: need 0 < lo < hi, got lo=%r, hi=%r' % (lo, hi))
    if not tolerance > 0:
        raise ValueError('bisect_threshold: tolerance=%r is out of range; allowed: > 0' % (tolerance,))
    trials = []

    def test(x):
        u = bool(is_unstable(x))
        trials.append((x, u))
        return u

    for _ in range(max_expand):
        if not test(lo):
            break
        hi, lo = lo, lo / 2
    else:
        raise RuntimeError('bisect_threshold: no stable value found down to %g' % lo)
    for _ in range(max_expand):
        if test(hi):
            break
        lo, hi = hi, hi * 2
    else:
        raise RuntimeError('bisect_threshold: no unstable value found up to %g' % hi)
    while hi / lo > 1 + tolerance:
        mid = math.sqrt(lo * hi)
        if test(mid):
            hi = mid
        else:
            lo = mid
    return lo, hi, trials
