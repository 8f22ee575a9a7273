#!/usr/bin/env python3
"""Reproduces the time-step study of docs/study.md: scans, CSVs (docs/data/) and figures.

    ./yadew sh python3 docs/make_study.py [-j JOBS] [--only explicit|implicit|figures]

The scans resume: finished cases are kept in docs/data/scan-*/results.jsonl, so an interrupted run
continues where it stopped.  Expect about 30 min on 2 cores for everything.
"""
import argparse
import csv
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), 'py'))

from viscbridge import criteria, scan  # noqa: E402

DATA = os.path.join(HERE, 'data')
FIGURES = os.path.join(HERE, 'figures')

BASE = dict(n=300, radius=0.5e-3, sizeRatio=1.0, viscosity=1.0, sMinRel=1e-3, normalModel='adamsPerchard',
            tangentialModel='slip', steps=2000, tolerance=0.03)
VISCOSITIES = [1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0, 1000.0]


def explicit_cases():
    cases = scan.one_at_a_time(BASE, viscosity=VISCOSITIES, sMinRel=[1e-4, 1e-3, 1e-2, 1e-1],
                               radius=[0.25e-3, 0.5e-3, 1e-3], sizeRatio=[1.0, 2.0, 3.0])
    cases += scan.one_at_a_time(dict(BASE, normalModel='pitois'), viscosity=VISCOSITIES)
    return cases


def implicit_cases():
    return scan.one_at_a_time(dict(BASE, integration='implicit'), viscosity=VISCOSITIES)


def theory(row):
    """The criteria of viscbridge.criteria for a scanned case (smallest particles, z from the bed)."""
    fuzz = (row['sizeRatio'] - 1) / (row['sizeRatio'] + 1)
    r = row['radius'] * (1 - fuzz)
    crit = criteria.critical_dt(r, row['density'], row['young'], row['poisson'], row['viscosity'],
                                s_min_rel=row['sMinRel'], normal_model=row['normalModel'],
                                tangential_model=row['tangentialModel'], integration=row['integration'],
                                coordination=max(1, round(row['coordination'])),
                                bridge_volume_rel=row['bridgeVolumeRel'])
    return crit


def write_csv(rows, path, keys):
    with open(path, 'w', newline='') as fh:
        w = csv.writer(fh)
        w.writerow(keys)
        for r in rows:
            w.writerow([r.get(k) for k in keys])


KEYS = ['integration', 'viscosity', 'sMinRel', 'radius', 'sizeRatio', 'normalModel', 'tangentialModel', 'n',
        'coordination', 'bridges', 'dt_stable', 'dt_unstable', 'dt_critical', 't_v', 'critical_over_tv',
        'dt_stepper', 'critical_over_stepper', 'governing', 'rayleigh_dt', 'pair_limit_2tv', 'network_bound',
        'network_over_critical', 'trials', 'wall_seconds']


def enrich(rows):
    for r in rows:
        c = theory(r)
        r['pair_limit_2tv'] = 2 * r['t_v'] if math.isfinite(r['t_v']) else None
        r['network_bound'] = c.stability_limit
        r['network_over_critical'] = c.stability_limit / r['dt_critical']
    return rows


def figures(explicit, implicit):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    os.makedirs(FIGURES, exist_ok=True)

    def base_like(r, **fixed):
        return all(r[k] == v for k, v in dict(BASE, **fixed).items() if k in ('radius', 'sizeRatio', 'sMinRel', 'normalModel'))

    # 1. critical Δt against viscosity: explicit AP and Pitois, implicit, theory lines
    fig, ax = plt.subplots(figsize=(7, 4.6))
    for model, marker in (('adamsPerchard', 'o'), ('pitois', 's')):
        pts = sorted((r['viscosity'], r['dt_critical']) for r in explicit if base_like(r, normalModel=model))
        ax.loglog(*zip(*pts), marker + '-', label='explicit, %s (measured)' % model)
    pts = sorted((r['viscosity'], r['dt_critical']) for r in implicit)
    ax.loglog(*zip(*pts), 'D-', label='implicit (measured)')
    mus = [r['viscosity'] for r in explicit if base_like(r)]
    mus.sort()
    base_rows = sorted((r for r in explicit if base_like(r)), key=lambda r: r['viscosity'])
    ax.loglog(mus, [r['pair_limit_2tv'] for r in base_rows], 'k--', label='pair limit 2 t_v (P12)')
    ax.loglog(mus, [r['network_bound'] for r in base_rows], 'k:', label='network bound P14 (z from the bed)')
    ax.loglog(mus, [r['dt_stepper'] for r in base_rows], 'g-.', label='ViscBridgeTimeStepper (safety 0.5)')
    ax.axhline(base_rows[0]['rayleigh_dt'], color='grey', lw=0.8, label='0.2 T_Rayleigh')
    ax.set_xlabel('viscosity μ [Pa·s]')
    ax.set_ylabel('critical Δt [s]')
    ax.set_title('Wetted bed of 300 spheres, r = 0.5 mm, S_min = 1e-3 r̄', fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(True, which='both', alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGURES, 'critical_dt_vs_viscosity.png'), dpi=110)
    plt.close(fig)

    # 2. ratio critical/t_v against each varied parameter
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.6), sharey=True)
    for ax, (field, label) in zip(axes, (('sMinRel', 'S_min / r̄'), ('radius', 'radius [m]'), ('sizeRatio', 'size ratio'))):
        pts = sorted((r[field], r['critical_over_tv']) for r in explicit
                     if r['viscosity'] == BASE['viscosity'] and r['normalModel'] == 'adamsPerchard'
                     and all(r[k] == BASE[k] for k in ('sMinRel', 'radius', 'sizeRatio') if k != field))
        ax.plot(*zip(*pts), 'o-')
        if field in ('sMinRel', 'radius'):
            ax.set_xscale('log')
        ax.set_xlabel(label)
        ax.grid(True, which='both', alpha=0.3)
    axes[0].set_ylabel('Δt_crit / t_v')
    fig.suptitle('Measured critical step in units of the pair decay time t_v (μ = 1 Pa·s)', fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGURES, 'critical_over_tv.png'), dpi=110)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    p.add_argument('-j', '--jobs', type=int, default=os.cpu_count() or 1)
    p.add_argument('--only', choices=['explicit', 'implicit', 'figures'])
    args = p.parse_args()
    os.makedirs(DATA, exist_ok=True)
    ex_dir, im_dir = os.path.join(DATA, 'scan-explicit'), os.path.join(DATA, 'scan-implicit')
    if args.only in (None, 'explicit'):
        scan.run_cases(explicit_cases(), ex_dir, jobs=args.jobs)
    if args.only in (None, 'implicit'):
        scan.run_cases(implicit_cases(), im_dir, jobs=args.jobs)
    explicit = enrich(scan.collect(ex_dir))
    implicit = enrich(scan.collect(im_dir)) if os.path.exists(os.path.join(im_dir, 'results.jsonl')) else []
    write_csv(sorted(explicit, key=lambda r: (r['normalModel'], r['viscosity'], r['sMinRel'], r['radius'], r['sizeRatio'])),
              os.path.join(DATA, 'critical_dt_explicit.csv'), KEYS)
    if implicit:
        write_csv(sorted(implicit, key=lambda r: r['viscosity']), os.path.join(DATA, 'critical_dt_implicit.csv'), KEYS)
    figures(explicit, implicit)
    print('wrote', os.path.join(DATA, 'critical_dt_explicit.csv'), 'and figures in', FIGURES)


if __name__ == '__main__':
    main()
