# The stability limit of wetted beds: bisected (energy criterion, and with the period-2 ringing),
# against what ViscBridgeTimeStepper estimates (the spectral limit P18, its dense check, and P14).
#
#   ./yadew run docs/make_spectral_table.py          (about 10 min; writes docs/data/spectral_limit.csv)
#
# Each bed: 300 spheres (r = 0.5 mm) settled dry, wetted (every contact a bridge at S_min) and
# perturbed by 1 cm/s, as in docs/study.md; the limit is bisected to 0.5 % over 2000 steps.
import csv
import math
import os
import sys

from yade import O
import yade.wrapper as yw

import viscbridge.scan as scan

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
CASES = [
    ('μ = 1, equal spheres, S_min = 1e-3 r̄', dict(viscosity=1.0)),
    ('μ = 1, size ratio 3', dict(viscosity=1.0, sizeRatio=3.0)),
    ('μ = 1, S_min = 0.1 r̄', dict(viscosity=1.0, sMinRel=0.1)),
    ('μ = 1e-2 (transition)', dict(viscosity=0.01)),
    ('μ = 1e-3 (collision regime)', dict(viscosity=0.001)),
]


def stepper_estimates(trial):
    """The stepper's limits (safety 1) at the start and their smallest values over the trial's steps, run
    at safety 0.5 (a stable path close to the bisection's fixed-Δt runs from the same state)."""
    trial.prepare()
    ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
    # prepare() cleared the interactions: a step of 1e-12 s (without the stepper) forms the bridges
    O.dt, ts.active = 1e-12, False
    O.run(1, True)
    ts.active = True
    exact = ts.exactLimit()
    ts.safety = 0.5
    low = dict(spectral=math.inf, spectral_safe=math.inf, p14=math.inf)
    for _ in range(trial.case['steps']):
        O.run(1, True)
        for key, attr in (('spectral', 'dtRitz'), ('spectral_safe', 'dtNetwork'), ('p14', 'dtP14')):
            low[key] = min(low[key], getattr(ts, attr) / ts.safety)
    return dict(low, exact=exact, governing=ts.governing)


rows = []
for label, kw in CASES:
    base = dict(n=300, seed=5, tolerance=0.005, **kw)
    est = stepper_estimates(scan._Trial(scan.normalize_case(base), scan.dry_bed(scan.normalize_case(base), os.path.join(HERE, 'data', 'beds'))))
    row = dict(case=label, **est)
    for verdict in ('energy', 'period2'):
        case = scan.normalize_case(dict(base, verdict=verdict))
        trial = scan._Trial(case, scan.dry_bed(case, os.path.join(HERE, 'data', 'beds')))
        lo, hi, _ = scan.bisect_threshold(lambda dt: trial.unstable_at(dt), 0.8 * est['exact'], 1.1 * est['exact'], case['tolerance'])
        row['critical_' + verdict] = math.sqrt(lo * hi)
    rows.append(row)
    print('%-40s energy %.4g  period-2 %.4g  spectral %.4g (dense %.4g)  P14 %.4g' % (
        label, row['critical_energy'], row['critical_period2'], row['spectral'], row['exact'], row['p14']), flush=True)

path = os.path.join(HERE, 'data', 'spectral_limit.csv')
with open(path, 'w', newline='') as fh:
    w = csv.DictWriter(fh, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
print('\n| bed | bisected Δt_crit, energy | with period-2 | spectral (stepper, safety 1) | P14 |\n|---|---|---|---|---|')
for r in rows:
    ref = r['critical_period2']
    print('| %s | %.4g s | %.4g s | %.3f× | %.3f× |' % (r['case'], r['critical_energy'], ref, r['spectral'] / ref, r['p14'] / ref))
print('\nwritten', path)
