"""The history of a settling run, written out: yade.plot.data as CSV, and a plot of the kinetic and
released potential energy, the time step and the number of bridges against time (matplotlib, Agg).
"""
import csv
import math
import os

__all__ = ['write_history_csv', 'log_limits', 'plot_history']


def write_history_csv(data, path):
    """yade.plot.data (dict of equal-length columns) as CSV with a header row.  An O.energy term
    (``E_...``) is 0 in the rows before it was first booked (yade.plot fills them with nan)."""
    keys = sorted(data, key=lambda k: (k not in ('t', 'iter', 'dt'), k))

    def column(k):
        if not k.startswith('E_'):
            return data[k]
        return [0.0 if isinstance(v, float) and math.isnan(v) else v for v in data[k]]
    rows = zip(*(column(k) for k in keys))
    tmp = path + '.part'
    with open(tmp, 'w', newline='') as fh:
        w = csv.writer(fh)
        w.writerow(keys)
        w.writerows(rows)
    os.replace(tmp, path)


def log_limits(series, decades=7):
    """y limits of a log plot showing the positive values of `series` (lists): from the smallest
    positive value, or `decades` below the largest if that is lower, to a little above the largest."""
    values = [v for s in series for v in s if v > 0 and math.isfinite(v)]
    if not values:
        return None
    top = max(values)
    return max(min(values), top * 10.0 ** -decades) / 2, top * 2


def plot_history(data, path, title='', stopped_at=None):
    """Kinetic and released potential energy (log scale) and the time step against time."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    t = list(data.get('t', []))
    fig, (ax, ax_dt) = plt.subplots(2, 1, figsize=(7, 5.6), sharex=True, gridspec_kw=dict(height_ratios=(2, 1)))
    series = []
    for key, label in (('Ek', 'kinetic energy'), ('Ereleased', 'released potential energy')):
        ys = list(data.get(key, []))
        # log scale: non-positive values (the start, before anything moved) are left out, not clamped
        pts = [(x, y) for x, y in zip(t, ys) if y > 0 and math.isfinite(y)]
        if pts:
            ax.semilogy(*zip(*pts), label=label)
            series.append([y for _, y in pts])
    limits = log_limits(series)
    if limits:
        ax.set_ylim(*limits)
    if stopped_at is not None:
        for a in (ax, ax_dt):
            a.axvline(stopped_at, color='tab:red', linestyle=':', linewidth=1.2)
        ax.annotate('stopped: unstable', (stopped_at, 1), xycoords=('data', 'axes fraction'), xytext=(-4, -12),
                    textcoords='offset points', ha='right', color='tab:red', fontsize=8)
    ax.set_ylabel('energy [J]')
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8, loc='lower right')
    ax.grid(True, which='both', alpha=0.3)
    dts = [(x, y) for x, y in zip(t, data.get('dt', [])) if y > 0]
    if dts:
        ax_dt.semilogy(*zip(*dts), color='black', linewidth=1.5, label='time step')
    ax_dt.set_ylabel('Δt [s]')
    ax_dt.set_xlabel('time [s]')
    ax_dt.grid(True, which='both', alpha=0.3)
    if 'bridges' in data:
        from matplotlib.ticker import MaxNLocator
        ax_b = ax_dt.twinx()
        ax_b.plot(t, data['bridges'], color='tab:green', linewidth=1)
        ax_b.set_ylabel('bridges', color='tab:green')
        ax_b.yaxis.set_major_locator(MaxNLocator(integer=True))
        ax_b.grid(False)  # the Δt axis' grid is the panel's; a second one would hide the Δt line
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)

