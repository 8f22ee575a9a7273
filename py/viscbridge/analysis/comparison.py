"""Several runs side by side (:func:`compare`): the agglomerate histories of runs (each an
``agglomerates.csv`` of :class:`~viscbridge.analysis.agglomerate_history.AgglomerateHistory` with its
sidecar ``agglomerates.json``) drawn over each other against revolutions or time, one colour per run,
labelled by the run parameters that differ between them ("viscosity = 5 Pa·s")::

    import viscbridge.analysis
    viscbridge.analysis.compare(['runs/mu5', 'runs/mu50'], 'cmp.png')

or, without YADE (plain python3 with numpy and matplotlib)::

    python3 -m viscbridge.analysis compare runs/mu5 runs/mu50 -o cmp.png

Panels: granules and agglomerates; the granulated mass fraction; the granule d50 and the largest
agglomerate; the coordination; the CoV of the liquid per particle.
"""
import collections
import csv
import json
import math
import os

import numpy

from .. import _checks
from .agglomerate_history import COLUMN_INFO, COLUMNS, SIDECAR_KIND, sidecar_path

__all__ = ['compare', 'read_run', 'run_labels', 'in_order', 'Run', 'Panel', 'PANELS', 'X_AXES', 'draw_panel']

X_AXES = {'revolutions': 'revolutions', 't': 'time [s]'}
"""What runs can be drawn against: column → axis label."""

Panel = collections.namedtuple('Panel', 'title ylabel lines log empty')
"""A panel: its title, its y label, the lines it draws ((column, line style), ...: one colour per
run, one style per column), whether its y axis is logarithmic, and what it says when no run has a
value to draw."""

PANELS = dict(
    # logarithmic: tens of granules beside hundreds of agglomerates
    granules=Panel('Granules (≥ 2 spheres) and agglomerates', 'number', (('granules', '-'), ('agglomerates', ':')),
                   True, 'no spheres'),
    mass=Panel('Granulated mass fraction', 'mass in granules / total mass', (('granulated_mass_fraction', '-'),), False,
               'no spheres'),
    size=Panel('Granule size (by mass) and largest', 'size [spheres]', (('granule_d50', '-'), ('largest', '--')), True,
               'no granule yet'),
    coordination=Panel('Coordination', 'bridges per sphere', (('coordination', '-'),), False, 'no spheres'),
    liquid=Panel('Liquid per particle', 'CoV of the liquid per sphere', (('liquid_cov', '-'),), False,
                 "no per-particle liquid (liquidModel 'fixed')"),
)
"""The panels of :func:`compare`, in order (AgglomerateHistory.plot draws some of them too)."""

Run = collections.namedtuple('Run', 'name path columns params units period')
"""A run read back: a name (its directory's), the CSV's path, its columns (name → numpy array), and
from the sidecar the run's parameters, their units and the period [s] (None if unknown)."""

_CSV = 'agglomerates.csv'


def _fail(run, why):
    raise ValueError('compare: runs entry %r %s' % (run, why))


def _csv_of(run):
    """The CSV of a `runs` entry: the directory's agglomerates.csv, or the entry itself."""
    if not isinstance(run, (str, os.PathLike)) or not str(run):
        _checks.reject('compare', 'runs', run, 'directories holding %s, or CSV files' % _CSV)
    path = os.fspath(run)
    if os.path.isdir(path):
        path = os.path.join(path, _CSV)
        if not os.path.isfile(path):
            _fail(run, 'is a directory without %s (no AgglomerateHistory recorded there)' % _CSV)
    elif not os.path.isfile(path):
        _fail(run, 'does not exist; allowed: a directory holding %s, or a CSV file' % _CSV)
    return path


def _name(run, path):
    """The run's directory name (or the CSV's name when it is not agglomerates.csv)."""
    if os.path.basename(path) == _CSV:
        return os.path.basename(os.path.dirname(os.path.abspath(path))) or path
    return os.path.splitext(os.path.basename(path))[0]


def _read_columns(run, path):
    with open(path, newline='') as fh:
        lines = [row for row in csv.reader(fh) if row]
    if not lines:
        _fail(run, 'is an empty file (%s): no header, no rows' % path)
    header, body = lines[0], lines[1:]
    missing = [c for c in COLUMNS if c not in header]
    if missing:
        _fail(run, 'is not a CSV of AgglomerateHistory as it is now (%s lacks the column(s) %s)' % (path, ', '.join(missing)))
    if body and len(body[-1]) != len(header):
        body = body[:-1]  # a last line cut by a kill mid-write
    if not body:
        _fail(run, 'has no rows yet (%s holds only its header)' % path)
    at = {c: header.index(c) for c in COLUMNS}
    try:
        return {c: numpy.array([float(row[k]) for row in body]) for c, k in at.items()}
    except (ValueError, IndexError):
        _fail(run, 'is not a CSV of AgglomerateHistory (%s has a row that is not a list of numbers)' % path)


def _read_sidecar(run, csv_path):
    """(params, units, period) of the sidecar beside the CSV; empty without one."""
    path = sidecar_path(csv_path)
    if not os.path.isfile(path):
        return {}, {}, None
    try:
        with open(path) as fh:
            side = json.load(fh)
    except ValueError as e:
        _fail(run, 'has a sidecar that is not JSON (%s: %s)' % (path, e))
    if not isinstance(side, dict) or side.get('kind') != SIDECAR_KIND:
        _fail(run, 'has a %s that is not the sidecar of an AgglomerateHistory' % path)
    return dict(side.get('params') or {}), dict(side.get('units') or {}), side.get('period')


def read_run(run):
    """A `runs` entry of :func:`compare` (a directory holding agglomerates.csv, or a CSV file) as a
    :class:`Run`; ValueError naming the entry for a missing, empty or foreign file."""
    path = _csv_of(run)
    params, units, period = _read_sidecar(run, path)
    return Run(_name(run, path), path, _read_columns(run, path), params, units, period)


def _value_text(name, value, unit):
    if value is None:
        return '%s unset' % name
    text = '%.4g' % value if isinstance(value, float) else str(value)
    return '%s = %s%s' % (name, text, ' ' + unit if unit else '')


def _differing(runs):
    """The parameters whose values differ between the :class:`Run` s, in the order the runs list them."""
    names = []
    for r in runs:
        names += [k for k in r.params if k not in names]
    return [k for k in names if len({json.dumps(r.params.get(k), sort_keys=True) for r in runs}) > 1]


def in_order(runs):
    """The :class:`Run` s sorted by the parameters that differ between them (numbers by value, then
    names, then unset), as a sweep reads; in the given order when none differ."""
    def value(v):
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return (0, v, '')
        return (1, 0, str(v)) if v is not None else (2, 0, '')
    differing = _differing(runs)
    return sorted(runs, key=lambda r: [value(r.params.get(k)) for k in differing])


def run_labels(runs):
    """Legend labels of :class:`Run` s: the parameters that differ between them ("viscosity = 5
    Pa·s, n = 300"), or, when none differ (or the runs have no sidecar), their directory names."""
    differing = _differing(runs)
    if differing:
        labels = [', '.join(_value_text(k, r.params.get(k), r.units.get(k, '')) for k in differing) for r in runs]
        if len(set(labels)) == len(labels):
            return labels
    labels = [r.name for r in runs]
    return labels if len(set(labels)) == len(labels) else [r.path for r in runs]


def _colours(n):
    import matplotlib.pyplot as plt
    if n <= 10:
        return ['C%d' % k for k in range(n)]
    return [plt.cm.viridis(k / (n - 1)) for k in range(n)]


def draw_panel(ax, panel, runs, x, colours):
    """Draw `panel` (a :class:`Panel`) for the :class:`Run` s `runs` against column `x` on the axes
    `ax`, run k in colour colours[k]; a panel of several columns gets a legend of its line styles."""
    from matplotlib.lines import Line2D
    drawn = False
    for run, colour in zip(runs, colours):
        for column, style in panel.lines:
            y = run.columns[column]
            finite = numpy.isfinite(y) & (y > 0 if panel.log else True)
            drawn = drawn or bool(finite.any())
            ax.plot(run.columns[x], numpy.where(finite, y, numpy.nan), color=colour, linestyle=style)
    if panel.log and drawn:
        import matplotlib.ticker as ticker
        ax.set_yscale('log')  # counts of 1 to 10³ spheres: labelled at 1, 2, 3, 5, 10, 20, ...
        ax.yaxis.set_major_locator(ticker.LogLocator(base=10, subs=(1, 2, 3, 5)))
        ax.yaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: '%g' % v))
        ax.yaxis.set_minor_formatter(ticker.NullFormatter())
    if not drawn:
        ax.text(0.5, 0.5, panel.empty, transform=ax.transAxes, ha='center', va='center', fontsize=9, color='0.4')
    if len(panel.lines) > 1:
        ax.legend([Line2D([], [], color='0.3', linestyle=s) for _, s in panel.lines],
                  [COLUMN_INFO[c].label for c, _ in panel.lines], fontsize=8, loc='best')
    ax.grid(True, which='major', alpha=0.3)
    ax.set_title(panel.title, fontsize=10)
    ax.set_xlabel(X_AXES[x])
    ax.set_ylabel(panel.ylabel)


def _checked_runs(runs, x):
    """The runs read back, each with finite values of `x` in every row."""
    if isinstance(runs, (str, os.PathLike)) or not isinstance(runs, (list, tuple)) or not runs:
        _checks.reject('compare', 'runs', runs, 'a non-empty list of directories holding %s, or of CSV files' % _CSV)
    out = [read_run(r) for r in runs]
    for given, run in zip(runs, out):
        if not numpy.isfinite(run.columns[x]).all():
            _fail(given, "has no %s (its history was recorded without drum=... or period=...); allowed for it: x='t'"
                  % x if x == 'revolutions' else 'has non-finite values of %s' % x)
    return out


def compare(runs, path, x='revolutions', labels=None, title=''):
    """Draw the agglomerate histories of `runs` over each other into `path` (.png, .pdf or .svg) and
    return `path`.

    `runs`: directories holding an agglomerates.csv of
    :class:`~viscbridge.analysis.agglomerate_history.AgglomerateHistory` (with its sidecar), or such
    CSV files.  `x`: 'revolutions' (the histories must know the drum's period) or 't' (time [s]).
    `labels`: one legend label per run, in the order of `runs` (default: the parameters that differ
    between the runs, as recorded in the sidecars, else the directory names; the runs are then
    drawn in the order of those parameters, e.g. by increasing viscosity).  Panels: granules and agglomerates; granulated
    mass fraction; granule d50 (by mass) and the largest agglomerate; coordination; CoV of the liquid
    per particle.  ValueError naming the argument for a missing, empty or foreign CSV, an unknown `x`
    or labels that do not match the runs."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    f = 'compare'
    _checks.choice(f, 'x', x, tuple(X_AXES))
    formats = ('.png', '.pdf', '.svg')
    if not isinstance(path, (str, os.PathLike)) or os.path.splitext(os.fspath(path))[1].lower() not in formats:
        _checks.reject(f, 'path', path, 'a file name ending in .png, .pdf or .svg')
    read = _checked_runs(runs, x)
    if labels is None:
        read = in_order(read)
        labels = run_labels(read)
    elif not isinstance(labels, (list, tuple)) or len(labels) != len(read) or not all(isinstance(s, str) for s in labels):
        _checks.reject(f, 'labels', labels, 'None or one string per run (%d)' % len(read))
    colours = _colours(len(read))
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.4))
    for ax, panel in zip(axes.flat, PANELS.values()):
        draw_panel(ax, panel, read, x, colours)
    key = axes.flat[len(PANELS)]
    key.axis('off')
    import textwrap  # a label of several parameters on lines of its own, within the panel
    labels = ['\n'.join(textwrap.wrap(s, 38)) for s in labels]
    key.legend([matplotlib.lines.Line2D([], [], color=c, linewidth=2) for c in colours], labels, loc='center',
               title='runs', fontsize=9, title_fontsize=10, frameon=False)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    path = os.fspath(path)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
