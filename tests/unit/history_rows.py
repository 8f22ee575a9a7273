"""Rows of an AgglomerateHistory made without YADE, for the tests of the history and of compare."""
import math

from viscbridge.analysis.agglomerate_history import statistics
from viscbridge.analysis.agglomerates import components


def record(history, t, edges, n=6):
    """Append to `history` a row of `n` spheres of unit mass joined by `edges` at time `t` [s] (as
    record() does on a scene; the first sphere holds all the liquid), and return it."""
    a = components(list(range(n)), edges, [1.0] * n, liquid=[1.0] + [0.0] * (n - 1))
    period = history.period
    return history._append(dict(t=t, iter=int(1000 * t), revolutions=t / period if period else math.nan,
                                **statistics(a), liquid_sprayed=0.0, broken=0, merged=0), a)
