"""Agglomerate statistics over a run: a CSV row per call and a plot (size distribution at chosen times,
number of agglomerates, largest and mass-median size over time).

    from viscbridge.analysis.agglomerate_history import AgglomerateHistory
    history = AgglomerateHistory('out/agglomerates.csv')
    O.engines = O.engines + [history.recorder(iterPeriod=2000)]
    O.run(100000, True)
    history.plot('out/agglomerates.png')

Each row is written to the CSV as it is recorded (a run stopped by Ctrl-C keeps what it logged).
"""
import math
import os

import numpy

from .. import _checks
from .agglomerates import agglomerates, transitions

__all__ = ['AgglomerateHistory', 'mass_median_size', 'COLUMNS']

COLUMNS = ('t', 'iter', 'spheres', 'agglomerates', 'largest', 'largest_mass_fraction', 'd50', 'mean_size',
           'coordination', 'liquid_cov', 'bridges', 'broken', 'merged')
"""The CSV's columns.  ``broken`` and ``merged``: agglomerates that broke and that formed by
coalescence since the previous row (:func:`~viscbridge.analysis.agglomerates.transitions`)."""


def mass_median_size(a):
    """d50 of the agglomerates by mass: the size (spheres) of the agglomerate at which the mass
    fraction, summed from the smallest, reaches one half."""
    order = numpy.argsort(a.sizes, kind='stable')
    cumulative = numpy.cumsum(a.mass_fractions[order])
    return int(a.sizes[order][numpy.searchsorted(cumulative, 0.5)]) if len(order) else 0


class AgglomerateHistory:
    """Records :func:`~viscbridge.analysis.agglomerates.agglomerates` statistics (``rows``, one dict per
    call, the columns of ``COLUMNS``) to `csv_path`, keeping each call's agglomerate sizes and mass
    fractions for :meth:`plot`.  `min_force`, `min_volume`: the edge thresholds of agglomerates()."""

    def __init__(self, csv_path, min_force=0.0, min_volume=0.0):
        if not isinstance(csv_path, str) or not csv_path:
            _checks.reject('AgglomerateHistory', 'csv_path', csv_path, 'a file name')
        self.csv_path, self.min_force, self.min_volume = csv_path, min_force, min_volume
        self.rows, self.snapshots = [], []
        self._last = None
        os.makedirs(os.path.dirname(os.path.abspath(csv_path)), exist_ok=True)
        with open(csv_path, 'w') as fh:
            fh.write(','.join(COLUMNS) + '\n')

    def record(self):
        """Measure O now and append a row (to ``rows`` and the CSV)."""
        from yade import O
        a = agglomerates(min_force=self.min_force, min_volume=self.min_volume)
        multi = a.sizes[a.sizes > 1]
        broken, merged = transitions(self._last, a) if self._last is not None else (0, 0)
        self._last = a
        row = dict(t=O.time, iter=O.iter, spheres=len(a.ids), agglomerates=a.count, largest=a.largest,
                   largest_mass_fraction=float(a.mass_fractions[0]) if a.count else math.nan, d50=mass_median_size(a),
                   mean_size=float(multi.mean()) if len(multi) else 1.0, coordination=a.coordination,
                   liquid_cov=a.liquid_cov if a.liquid_cov is not None else math.nan,
                   bridges=int(round(a.coordination * len(a.ids) / 2)), broken=broken, merged=merged)
        self.rows.append(row)
        self.snapshots.append((O.time, a.sizes.copy(), a.mass_fractions.copy()))
        with open(self.csv_path, 'a') as fh:
            fh.write(','.join('%.9g' % row[c] if isinstance(row[c], float) else str(row[c]) for c in COLUMNS) + '\n')
        return row

    def recorder(self, iterPeriod=None, virtPeriod=None):
        """A PyRunner that calls :meth:`record` every `iterPeriod` steps or `virtPeriod` seconds."""
        import yade.wrapper as yw
        if (iterPeriod is None) == (virtPeriod is None):
            raise ValueError('AgglomerateHistory.recorder: give exactly one of iterPeriod=... or virtPeriod=... [s]')
        _HISTORIES.append(self)
        # binds only the name `viscbridge` in the user's namespace (an alias would clobber their own)
        command = ('import viscbridge.analysis.agglomerate_history; '
                   'viscbridge.analysis.agglomerate_history._HISTORIES[%d].record()' % (len(_HISTORIES) - 1))
        if iterPeriod is not None:
            return yw.PyRunner(iterPeriod=_checks.integer('recorder', 'iterPeriod', iterPeriod, minimum=1), command=command, initRun=True)
        return yw.PyRunner(virtPeriod=_checks.positive('recorder', 'virtPeriod', virtPeriod, ' [s]'), command=command, initRun=True)

    def plot(self, path, times=None, title=''):
        """Write a PNG: (left) the mass distribution over agglomerate size at `times` [s] (default:
        four times spread over the record), (middle) the number of agglomerates, the largest and the
        mass-median size d50 over time, (right) breakage and coalescence events summed over time."""
        import matplotlib
        import matplotlib.ticker
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
        if not self.rows:
            raise ValueError('AgglomerateHistory.plot: nothing recorded yet (call record() or run with recorder())')
        recorded = [t for t, _, _ in self.snapshots]
        if times is None:
            picks = sorted({int(round(k * (len(recorded) - 1) / 3)) for k in range(4)})
        else:
            picks = [int(numpy.argmin([abs(r - t) for r in recorded])) for t in times]
        fig, (left, right, events) = plt.subplots(1, 3, figsize=(15, 4.2))
        top = max(int(s.max()) for _, s, _ in self.snapshots)
        edges = [0.5] + [2 ** k + 0.5 for k in range(int(math.ceil(math.log2(max(top, 2)))) + 1)]
        width = 0.8 / len(picks)
        for k, i in enumerate(picks):
            t, sizes, mass = self.snapshots[i]
            counts, _ = numpy.histogram(sizes, bins=edges, weights=mass)
            left.bar(numpy.arange(len(counts)) + (k - (len(picks) - 1) / 2) * width, counts, width=width,
                     color=plt.cm.viridis(k / max(1, len(picks) - 1)), label='t = %.3g s' % t)
        left.set_xticks(range(len(edges) - 1))
        bounds = [(int(lo) + 1, int(hi)) for lo, hi in zip(edges[:-1], edges[1:])]
        left.set_xticklabels(['%d' % lo if lo == hi else '%d–%d' % (lo, hi) for lo, hi in bounds], rotation=45, fontsize=8)
        left.set_xlabel('agglomerate size [spheres]')
        left.set_ylabel('mass fraction')
        left.set_title('Size distribution (by mass)')
        left.legend(fontsize=8)
        t = [r['t'] for r in self.rows]
        right.plot(t, [r['agglomerates'] for r in self.rows], 'C0-', label='agglomerates (number)')
        right.set_xlabel('time [s]')
        right.set_ylabel('number of agglomerates', color='C0')
        twin = right.twinx()
        twin.plot(t, [r['largest'] for r in self.rows], 'C3-', label='largest [spheres]')
        twin.plot(t, [r['d50'] for r in self.rows], 'C2--', label='d50 by mass [spheres]')
        twin.set_ylabel('size [spheres]')
        twin.grid(False)
        lines = right.get_lines() + twin.get_lines()
        right.legend(lines, [line.get_label() for line in lines], fontsize=8, loc='upper center', bbox_to_anchor=(0.5, -0.15), ncol=3)
        right.set_title('Growth over time')
        for column, colour, label in (('merged', 'C0', 'formed by coalescence'), ('broken', 'C3', 'broken')):
            events.step(t, numpy.cumsum([r[column] for r in self.rows]), colour, where='post', label=label)
        events.set_xlabel('time [s]')
        events.set_ylabel('agglomerates (summed since the start)')
        events.set_title('Coalescence and breakage')
        events.yaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))  # counts
        events.legend(fontsize=8)
        if title:
            fig.suptitle(title, fontsize=10)
        fig.tight_layout()
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        fig.savefig(path, dpi=110)
        plt.close(fig)
        return path


_HISTORIES = []
