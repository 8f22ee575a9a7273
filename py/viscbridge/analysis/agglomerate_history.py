"""Agglomerate statistics over a run: a CSV row per call, the run's parameters beside it, and a plot
(size distribution at chosen times, granules, granulated mass fraction, granule size, liquid or
coordination, coalescence and breakage over time or revolutions)::

    from viscbridge.analysis.agglomerate_history import AgglomerateHistory
    d = scenes.drum(viscosity=5.0)
    history = AgglomerateHistory('out/agglomerates.csv', drum=d)   # writes out/agglomerates.json too
    O.engines = O.engines + [history.recorder(virtPeriod=d.period / 16)]
    d.run(revolutions=3)
    history.plot('out/agglomerates.png')                          # against revolutions

Each row is appended to the CSV as it is recorded (a run stopped by Ctrl-C keeps what it logged).
The sidecar ``<csv name>.json`` (:func:`sidecar_path`), written when the history is made, holds the
run's parameters with their units and the meaning and unit of every column: what
:func:`viscbridge.analysis.compare` reads to label runs by the parameters that differ between them.

Words used by the columns: an *agglomerate* is a connected component of the bridge graph, a single
sphere included (a clump counts as one sphere); a *granule* is an agglomerate of at least two
spheres.
"""
import collections
import json
import math
import numbers
import os

import numpy

from .. import _checks, _registry, liquid, mpi
from .agglomerates import agglomerates, transitions

__all__ = ['AgglomerateHistory', 'Column', 'COLUMN_INFO', 'COLUMNS', 'mass_median_size', 'granule_mass_median_size',
           'statistics', 'sidecar_path', 'SIDECAR_KIND']

Column = collections.namedtuple('Column', 'unit label meaning')
"""A column of the CSV: its unit ('' for a count or a ratio), a short label for plots, its meaning."""

COLUMN_INFO = dict(
    t=Column('s', 'time', 'simulated time (O.time)'),
    iter=Column('', 'step', 'step number (O.iter)'),
    revolutions=Column('', 'revolutions', 'revolutions turned, t / period; nan when the history knows no period '
                                          '(AgglomerateHistory(drum=...) or period=...)'),
    spheres=Column('', 'spheres', 'dynamic spheres, the members of the agglomerates (a clump counts as one)'),
    agglomerates=Column('', 'agglomerates', 'agglomerates, single spheres included: equal to spheres before any '
                                            'bridge forms'),
    granules=Column('', 'granules', 'granules: agglomerates of at least 2 spheres'),
    largest=Column('spheres', 'largest', 'spheres in the largest agglomerate (1 while no bridge joins two spheres)'),
    largest_mass_fraction=Column('', 'largest mass fraction', 'mass of the largest agglomerate / mass of all spheres'),
    d50=Column('spheres', 'd50 of all', 'mass-median agglomerate size, single spheres included: 1 until half of the '
                                         'mass is in granules'),
    granule_d50=Column('spheres', 'granule d50', 'mass-median size of the granules alone; nan while there is no granule'),
    granule_mean_size=Column('spheres', 'granule mean size', 'mean number of spheres per granule; nan while there is '
                                                             'no granule'),
    granulated_mass_fraction=Column('', 'granulated mass fraction', 'mass in granules / mass of all spheres (0 before '
                                                                    'any bridge forms)'),
    coordination=Column('', 'coordination', 'bridges between spheres per sphere (each bridge counted at both ends)'),
    liquid_cov=Column('', 'liquid CoV', 'coefficient of variation of the liquid per sphere (film + share of its '
                                        'bridges); nan without per-particle liquid (liquidModel fixed)'),
    liquid_sprayed=Column('m³', 'liquid sprayed', 'liquid the sprays have put into the films so far '
                                                  '(viscbridge.liquid.sprayed(); 0 without sprays)'),
    bridges=Column('', 'bridges', 'bridges between two spheres'),
    broken=Column('', 'broken', "agglomerates of the previous row whose spheres now lie in more than one "
                                "(breakage or erosion since the previous row; 0 in the first row, nan in the first "
                                "row of a process that loaded the saved scene)"),
    merged=Column('', 'merged', 'agglomerates made of spheres of more than one agglomerate of the previous row '
                                '(coalescence or layering since the previous row; 0 in the first row, nan in the '
                                'first row of a process that loaded the saved scene)'),
)
"""Every column of the CSV, in order, with its unit, plot label and meaning (the one list of them)."""

COLUMNS = tuple(COLUMN_INFO)
"""The CSV's columns, in order."""

SIDECAR_KIND = 'viscbridge.analysis.agglomerate_history'
"""The ``kind`` entry of a sidecar: how a reader tells it from other JSON files."""


def sidecar_path(csv_path):
    """The sidecar of the CSV `csv_path`: the same name with ``.json`` (agglomerates.csv → agglomerates.json)."""
    return os.path.splitext(csv_path)[0] + '.json'


def _mass_median(sizes, masses):
    """The size at which the mass, summed from the smallest size, reaches half of the total."""
    order = numpy.argsort(sizes, kind='stable')
    cumulative = numpy.cumsum(masses[order]) / masses.sum()
    return int(sizes[order][min(numpy.searchsorted(cumulative, 0.5), len(order) - 1)])


def mass_median_size(a):
    """d50 of all the agglomerates of `a` (single spheres included) by mass: the size [spheres] at which
    the mass, summed from the smallest agglomerate, reaches one half; 0 without spheres."""
    return _mass_median(a.sizes, a.masses) if a.count else 0


def granule_mass_median_size(a):
    """d50 of the granules of `a` alone (agglomerates of at least 2 spheres) by mass [spheres]; nan
    without granules."""
    granule = a.sizes > 1
    return float(_mass_median(a.sizes[granule], a.masses[granule])) if granule.any() else math.nan


def statistics(a):
    """The measures of one :class:`~viscbridge.analysis.agglomerates.Agglomerates` `a`, as the columns
    of COLUMNS from ``spheres`` to ``bridges`` (no time, no liquid sprayed, no transitions).  Plain
    Python: `a` may come from :func:`~viscbridge.analysis.agglomerates.components`."""
    granule = a.sizes > 1
    total = a.masses.sum()
    return dict(
        spheres=len(a.ids), agglomerates=a.count, granules=int(granule.sum()), largest=a.largest,
        largest_mass_fraction=float(a.mass_fractions[0]) if a.count else math.nan, d50=mass_median_size(a),
        granule_d50=granule_mass_median_size(a),
        granule_mean_size=float(a.sizes[granule].mean()) if granule.any() else math.nan,
        granulated_mass_fraction=float(a.masses[granule].sum() / total) if total > 0 else math.nan,
        coordination=a.coordination, liquid_cov=a.liquid_cov if a.liquid_cov is not None else math.nan,
        bridges=int(round(a.coordination * len(a.ids) / 2)) if len(a.ids) else 0)


def _checked_params(name, params, allowed, plain):
    """`params` as a dict of names to values that `plain` accepts (ValueError naming `name` otherwise)."""
    if not isinstance(params, dict) or not all(isinstance(k, str) and plain(v) for k, v in params.items()):
        _checks.reject('AgglomerateHistory', name, params, allowed)
    return {k: v if v is None or isinstance(v, (bool, str)) else (int(v) if isinstance(v, numbers.Integral) else float(v))
            for k, v in params.items()}


def _plain_value(v):
    return v is None or isinstance(v, (bool, str)) or (isinstance(v, numbers.Real) and math.isfinite(v))


def _cell(value):
    return '%.9g' % value if isinstance(value, float) else str(value)


class AgglomerateHistory:
    """Records :func:`~viscbridge.analysis.agglomerates.agglomerates` statistics (``rows``, one dict per
    call with the columns of COLUMNS) to `csv_path`, keeping each call's agglomerate sizes and mass
    fractions for :meth:`plot`.

    `drum`: the :func:`viscbridge.scenes.drum` handle of the run: its period gives the
    ``revolutions`` column (O.time / period: the drum turns from t = 0) and its parameters and their
    units go into the sidecar.  Other scenes: `period` [s] for a ``revolutions`` column, or neither
    (the column is nan).  `params`: the run's parameters for the sidecar (names to finite numbers,
    strings, True/False or None), added to the drum's (a name in both takes the value of `params`);
    `units`: their units (names to strings; a name of the Ip2's numeric parameters, such as
    viscosity, has its unit without it).  `min_force`, `min_volume`: the edge thresholds of
    agglomerates().  The CSV's header and the sidecar (:func:`sidecar_path`) are written here,
    replacing earlier ones."""

    def __init__(self, csv_path, min_force=0.0, min_volume=0.0, drum=None, period=None, params=None, units=None):
        f = 'AgglomerateHistory'
        if not isinstance(csv_path, str) or not csv_path or csv_path.endswith('.json'):
            _checks.reject(f, 'csv_path', csv_path, 'a file name not ending in .json (the sidecar takes that name)')
        self.min_force = _checks.non_negative(f, 'min_force', min_force, ' [N]')
        self.min_volume = _checks.non_negative(f, 'min_volume', min_volume, ' [m³]')
        if drum is not None and period is not None:
            raise ValueError('AgglomerateHistory: give drum=... or period=... [s], not both (a drum has its period)')
        params = _checked_params('params', {} if params is None else params, 'a dict of names to finite numbers, '
                                 'strings, True/False or None', _plain_value)
        units = _checked_params('units', {} if units is None else units, 'a dict of names to unit strings',
                                lambda u: isinstance(u, str))
        self.params, given_units = {}, {k: p['unit'] for k, p in _registry.PARAMETERS.items()}
        if drum is not None:
            if not all(hasattr(drum, a) for a in ('period', 'params', 'units')):
                _checks.reject(f, 'drum', drum, 'the handle viscbridge.scenes.drum(...) returns')
            period = drum.period
            self.params = _checked_params('drum', drum.params, "a drum handle's parameters", _plain_value)
            given_units.update(drum.units)
        self.period = None if period is None else _checks.positive(f, 'period', period, ' [s]')
        self.params.update(params)
        given_units.update(units)
        self._start(csv_path, [], None)
        if not self._writes:
            return
        _warn_replacing(csv_path)
        os.makedirs(os.path.dirname(os.path.abspath(csv_path)), exist_ok=True)
        with open(csv_path, 'w') as fh:
            fh.write(','.join(COLUMNS) + '\n')
        sidecar = dict(kind=SIDECAR_KIND, csv=os.path.basename(csv_path), period=self.period, params=self.params,
                       min_force=self.min_force, min_volume=self.min_volume,
                       units={k: given_units.get(k, '') for k in self.params},
                       columns={name: dict(unit=c.unit, meaning=c.meaning) for name, c in COLUMN_INFO.items()})
        with open(sidecar_path(csv_path), 'w') as fh:
            json.dump(sidecar, fh, indent=1, ensure_ascii=False)
            fh.write('\n')

    def _start(self, csv_path, rows, last):
        """The state of a history about to record its next row after `rows`, `last` the agglomerates of
        the last one (None: not known)."""
        self.csv_path, self.rows, self.snapshots, self._rows_loaded = csv_path, rows, [], len(rows)
        self._last, self._runners = last, []
        # under yade.mpy every rank measures (agglomerates() is a collective) and rank 0 writes the files
        self._writes = mpi.rank() == 0
        _HISTORIES[os.path.abspath(csv_path)] = self
        # the command of its recorders (recorder()): with the CSV from the root, so that a process that
        # loads the saved scene finds the files to go on with (_recorded)
        self.command = ('import viscbridge.analysis.agglomerate_history; '
                        'viscbridge.analysis.agglomerate_history._recorded(%r)' % os.path.abspath(csv_path))

    @classmethod
    def resume(cls, csv_path):
        """The history that writes `csv_path` in this process: the one made here, or else one that goes on
        from the CSV and its sidecar — what a recorder saved with its scene uses after ``O.load`` in
        another process, and what you call there to plot it.  The first row it records has nan
        transitions (``broken``, ``merged``: the agglomerates of the row before are not saved), and its
        plot's size distribution shows the rows recorded in this process."""
        known = _HISTORIES.get(os.path.abspath(csv_path))
        return known if known is not None else cls._from_files(csv_path)

    @classmethod
    def _from_files(cls, csv_path):
        side = sidecar_path(csv_path)
        if not (os.path.exists(csv_path) and os.path.exists(side)):
            raise RuntimeError('AgglomerateHistory.resume: no history writes %s in this process, and %s is not there to go '
                               'on from (a recorder saved with its scene goes on from the CSV and its sidecar); make a new '
                               'AgglomerateHistory and recorder after O.load (and remove the old recorder from O.engines)'
                               % (csv_path, csv_path if not os.path.exists(csv_path) else side))
        with open(side) as fh:
            sidecar = json.load(fh)
        history = cls.__new__(cls)
        history.min_force, history.min_volume = sidecar.get('min_force', 0.0), sidecar.get('min_volume', 0.0)
        history.period, history.params = sidecar.get('period'), sidecar.get('params', {})
        with open(csv_path) as fh:
            header = fh.readline().strip().split(',')
            rows = [dict(zip(header, (_value(v) for v in line.strip().split(',')))) for line in fh if line.strip()]
        history._start(csv_path, rows, None)
        from yade import O
        history._runners = [e for e in O.engines if getattr(e, 'command', None) == history.command]
        return history

    def record(self, after_step=False):
        """Measure O now and append a row (to ``rows`` and the CSV); returns the row — the last one,
        unchanged, when this state is recorded already (the recorder writes the row a run ends in).
        `after_step`: called from within a step, after the integrator (the recorder): the state is
        that of the step's end, iteration O.iter + 1 at O.time + O.dt.  A call by hand counts as one
        of the :meth:`recorder` s': their periods restart from it."""
        from yade import O
        iteration, now = (O.iter + 1, O.time + O.dt) if after_step else (O.iter, O.time)
        if self.rows and self.rows[-1]['iter'] == iteration:
            return self.rows[-1]
        if self.rows and self.rows[-1]['iter'] > iteration:
            raise RuntimeError(
                'AgglomerateHistory: %s has rows up to step %d, past this scene\'s step %d: the scene was saved earlier and '
                'run on from there before, or the file belongs to another run. A run branched from a saved state needs a '
                'history of its own: remove the recorder whose command names this file from O.engines and make a new '
                'AgglomerateHistory(...) with another file.' % (self.csv_path, self.rows[-1]['iter'], iteration))
        for runner in self._runners:
            runner.virtLast, runner.iterLast, runner.nDone = O.time, O.iter, max(runner.nDone, 1)
        a = agglomerates(min_force=self.min_force, min_volume=self.min_volume)
        if self._last is not None:
            broken, merged = transitions(self._last, a)
        else:  # the first row (0), or the first of a resumed history, whose last row's agglomerates are unknown
            broken, merged = (math.nan, math.nan) if self.rows else (0, 0)
        self._last = a
        row = dict(t=now, iter=iteration, revolutions=now / self.period if self.period else math.nan,
                   **statistics(a), liquid_sprayed=liquid.sprayed(), broken=broken, merged=merged)
        return self._append(row, a)

    def _append(self, row, a):
        """Append `row` (every column of COLUMNS) measured on the agglomerates `a` to ``rows`` and the CSV."""
        self.rows.append(row)
        self.snapshots.append((row['t'], a.sizes.copy(), a.mass_fractions.copy()))
        if not self._writes:
            return row
        with open(self.csv_path, 'a') as fh:
            fh.write(','.join(_cell(row[c]) for c in COLUMNS) + '\n')
        return row

    def recorder(self, iterPeriod=None, virtPeriod=None):
        """A recorder (:yref:`ViscBridgeRecorder`, a PyRunner) that calls :meth:`record` every
        `iterPeriod` steps or `virtPeriod` seconds and in the last step of every run (``O.run(n)``, a
        run to ``O.stopAtTime`` such as ``Drum.run``, ``O.step()``), so that the state a run ends in
        is always a row; the state it is made in is the first row.  Append it to O.engines (after
        the integrator, where ``O.engines + [...]`` puts it)."""
        import yade.wrapper as yw
        from yade import O
        if (iterPeriod is None) == (virtPeriod is None):
            raise ValueError('AgglomerateHistory.recorder: give exactly one of iterPeriod=... or virtPeriod=... [s]')
        if iterPeriod is not None:
            iterPeriod = _checks.integer('recorder', 'iterPeriod', iterPeriod, minimum=1)
        else:
            virtPeriod = _checks.positive('recorder', 'virtPeriod', virtPeriod, ' [s]')
        self.record()  # the state the run starts from
        if iterPeriod is not None:
            # the runner ends steps O.iter + period − 1, + 2·period − 1, ...: rows at O.iter + period, ...
            runner = yw.ViscBridgeRecorder(iterPeriod=iterPeriod, firstIterRun=O.iter + iterPeriod - 1, command=self.command)
        else:
            runner = yw.ViscBridgeRecorder(virtPeriod=virtPeriod, command=self.command)
        self._runners.append(runner)
        return runner

    def plot(self, path, times=None, title='', x=None):
        """Write a PNG of the rows recorded so far: the mass distribution over agglomerate size at
        `times` [s] (default: four times spread over the record); the granules and agglomerates, the
        granulated mass fraction, the granule d50 and the largest agglomerate, the liquid's CoV (the
        coordination without per-particle liquid) and the agglomerates broken and formed by coalescence,
        against `x`: 'revolutions' (the default when the history knows a period) or 't' (time).  The
        PNG's ``Description`` metadata says how many rows it shows.  Returns `path`."""
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
        from . import comparison
        if not self.rows:
            raise ValueError('AgglomerateHistory.plot: nothing recorded yet (call record() or run with recorder())')
        if x is None:
            x = 'revolutions' if self.period else 't'
        _checks.choice('AgglomerateHistory.plot', 'x', x, tuple(comparison.X_AXES))
        if x == 'revolutions' and not self.period:
            raise ValueError("AgglomerateHistory.plot: x='revolutions' needs a period: make the history with drum=... "
                             "or period=... [s]; allowed without: x='t'")
        run = comparison.Run(os.path.basename(self.csv_path), self.csv_path,
                             {c: numpy.array([r[c] for r in self.rows], dtype=float) for c in COLUMNS},
                             self.params, {}, self.period)
        fig, axes = plt.subplots(2, 3, figsize=(15, 8.4))
        self._plot_distribution(axes[0, 0], times, plt)
        liquid_panel = 'liquid' if numpy.isfinite(run.columns['liquid_cov']).any() else 'coordination'
        for ax, name in zip((axes[0, 1], axes[0, 2], axes[1, 0], axes[1, 1]), ('granules', 'mass', 'size', liquid_panel)):
            comparison.draw_panel(ax, comparison.PANELS[name], [run], x, ['C0'])
        _plot_events(axes[1, 2], run, x)
        if title:
            fig.suptitle(title, fontsize=10)
        fig.tight_layout()
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        last = self.rows[-1]
        fig.savefig(path, dpi=100, metadata={'Description': '%d rows of %s up to t = %.6g s (%s revolutions)' % (
            len(self.rows), self.csv_path, last['t'], _cell(last['revolutions']))})
        plt.close(fig)
        return path

    def _plot_distribution(self, ax, times, plt):
        """The mass distribution over agglomerate size (doubling bins) at `times` [s]."""
        recorded = [t for t, _, _ in self.snapshots]
        if not recorded:  # a resumed history before its first row in this process
            ax.text(0.5, 0.5, 'no size distribution recorded\nin this process yet', ha='center', va='center',
                    transform=ax.transAxes)
            ax.axis('off')
            return
        if times is None:
            picks = sorted({int(round(k * (len(recorded) - 1) / 3)) for k in range(4)})
        else:
            picks = [int(numpy.argmin([abs(r - t) for r in recorded])) for t in times]
        top = max(int(s.max()) if len(s) else 1 for _, s, _ in self.snapshots)
        edges = [0.5] + [2 ** k + 0.5 for k in range(int(math.ceil(math.log2(max(top, 2)))) + 1)]
        width = 0.8 / len(picks)
        for k, i in enumerate(picks):
            t, sizes, mass = self.snapshots[i]
            counts, _ = numpy.histogram(sizes, bins=edges, weights=mass)
            when = 't = %.3g s' % t + (' (%.2f rev.)' % (t / self.period) if self.period else '')
            ax.bar(numpy.arange(len(counts)) + (k - (len(picks) - 1) / 2) * width, counts, width=width,
                   color=plt.cm.viridis(k / max(1, len(picks) - 1)), label=when)
        ax.set_xticks(range(len(edges) - 1))
        bounds = [(int(lo) + 1, int(hi)) for lo, hi in zip(edges[:-1], edges[1:])]
        ax.set_xticklabels(['%d' % lo if lo == hi else '%d–%d' % (lo, hi) for lo, hi in bounds], rotation=45, fontsize=8)
        ax.set_xlabel('agglomerate size [spheres]')
        ax.set_ylabel('mass fraction')
        ax.grid(True, axis='y', alpha=0.3)
        # the sizes of rows recorded by another process are not in the CSV
        ax.set_title('Size distribution (by mass)' + (', rows since loading' if self._rows_loaded else ''), fontsize=10)
        ax.legend(fontsize=8)


def _plot_events(ax, run, x):
    """Agglomerates broken and formed by coalescence, summed since the first row, against `x`."""
    import matplotlib.ticker
    from .comparison import X_AXES
    for column, colour, label in (('merged', 'C0', 'formed by coalescence'), ('broken', 'C3', 'broken')):
        # nancumsum: the unknown transitions of a resumed history's first row count as none
        ax.step(run.columns[x], numpy.nancumsum(run.columns[column]), colour, where='post', label=label)
    ax.set_xlabel(X_AXES[x])
    ax.set_ylabel('agglomerates (summed since the start)')
    ax.grid(True, alpha=0.3)
    ax.set_title('Coalescence and breakage', fontsize=10)
    ax.yaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))  # counts
    ax.legend(fontsize=8)


def _warn_replacing(csv_path):
    """A warning when a new history replaces the rows of an earlier one (AgglomerateHistory.resume goes on with them)."""
    try:
        with open(csv_path) as fh:
            rows = sum(1 for line in fh if line.strip()) - 1
    except OSError:
        return
    if rows > 0:
        import warnings
        warnings.warn('AgglomerateHistory: %s had %d row%s, now replaced by this new history (AgglomerateHistory.resume(%r) '
                      'would have gone on with them)' % (csv_path, rows, '' if rows == 1 else 's', csv_path), stacklevel=3)


def _value(cell):
    """A CSV cell as it was recorded: an int (counts, steps) or a float."""
    return int(cell) if cell.lstrip('-').isdigit() else float(cell)


_HISTORIES = {}  # by the CSV's absolute path: the histories of this process, where their recorders find them


def _recorded(csv_path):
    """The recorders' command: a row of the history of `csv_path` (absolute) at the end of this step;
    in a process that loaded the saved scene, the history goes on from its files."""
    return AgglomerateHistory.resume(csv_path).record(after_step=True)
