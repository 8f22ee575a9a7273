# Accuracy as the input: the error a tolerance achieves and what it costs, against the oracle.
#
#   ./yadew run bench/accuracy_target.py [--cases bed45,settling300] [--mu 1,10,100,1000] [--tol 1e-1,1e-2,1e-3]
#   ./yadew run bench/accuracy_target.py --cases pair,pair_implicit --mu 1 --tol 1e-1,1e-2,1e-3,1e-4
#   ./yadew run bench/accuracy_target.py --calibration [--cases ...] [--mu ...]   # error ÷ estimate, fixed Δt
# (about 1.5 min for --cases bed45, 12 min for --cases settling300 with its explicit oracle at
# 1000 Pa·s, 3 min for the pair cases, 1.5 min for --calibration --cases bed45, on the development
# VM; the cases are those of bench/accuracy_case.py: bed45, settling300, pair, pair_implicit)
#
# For each case of bench/accuracy_case.py and each viscosity: a reference run; the runs with
# viscbridge.engines(accuracy=tol) (integration 'auto': the stepper picks the scheme and Δt) for each
# tolerance; and the oracle of each tolerance — the cheapest fixed setting (explicit with the time
# stepper at safety 1, ½, ¼, …; implicit at a fixed Δt on a ladder) whose error meets it, found by
# running the settings from the cheapest down.  Cost: wall-clock time of the engines (YADE's timers).
# Goals (issue 25): achieved error <= tolerance, cost <= 2x the oracle's.
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # yade -x: __file__ is yade's own
import accuracy_case as ac  # noqa: E402
import common  # noqa: E402
from yade import O  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument('--cases', default='bed45,settling300')
parser.add_argument('--mu', default='1,10,100,1000')
parser.add_argument('--tol', default='1e-1,1e-2,1e-3')
parser.add_argument('--replot', action='store_true', help='only redraw the figure from docs/perf/accuracy_target_summary.csv')
parser.add_argument('--calibration', action='store_true',
                    help='instead: the estimate against the true error of fixed implicit steps (the ladder, held by the '
                         "stepper's maxDt), per case and viscosity, to docs/perf/accuracy_calibration.csv")
args = parser.parse_args(sys.argv[1:])
CASES = [ac.CASES[c]() for c in args.cases.split(',')]
VISCOSITIES = [float(m) for m in args.mu.split(',')]
TOLERANCES = sorted((float(t) for t in args.tol.split(',')), reverse=True)
SAFETIES = [1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125]
# implicit Δt = T/10/k: k = 2 is 5e-6 s on bed45 (below its collision step), 32 is 6.25e-6 s on settling300
IMPLICIT_K = {'bed45': [2, 4, 16, 64, 256, 1024], 'settling300': [32, 64, 128, 256, 1024], 'pair': [4, 16, 64, 256, 1024, 4096]}
IMPLICIT_K['pair_implicit'] = IMPLICIT_K['pair']
IMPLICIT_K.update(wall=[4, 16, 64, 256, 1024], capillary=[4, 16, 64, 256, 1024, 4096])
# the calibration's steps, where the first four of the ladder are above the stepper's own limit (the
# capillary pair's Rayleigh bound, 8.7e-6 s: maxDt would not hold Δt)
CALIBRATION_K = {'capillary': [1024, 2048, 4096, 8192]}
# The references: implicit at Δt = T/10/k, 6.1e-10 s on bed45 (at 2.4e-9 s its own error in the
# integrated e_K was 2.7e-4 at 100 Pa·s, above the tightest tolerance), 4.9e-8 s on settling300.  Not accuracy_cost's explicit run at a quarter of
# the stepper's limit: at 1 Pa·s its own error is 1.1e-3, as large as the tightest tolerance.
REFERENCE_K = {'bed45': 16384, 'settling300': 4096, 'pair': 65536, 'pair_implicit': 65536, 'wall': 16384, 'capillary': 16384}


def reference_run(case, mu):
    """The reference run, its scheme and its steps per sample interval."""
    k, integration = REFERENCE_K[case.name], 'implicit'
    ref = ac.run_fixed(case, mu, integration, k, slopes=True)
    assert not ref['why'], ref['why']
    return ref, integration, k


def reference(case, mu):
    """The reference run and its own error (the same scheme at twice the step)."""
    ref, integration, k = reference_run(case, mu)
    coarse = ac.run_fixed(case, mu, integration, max(1, k // 2))
    return ref, max(ac.errors(coarse, ref)), integration, case.T / ac.SAMPLES / k


def row(case, mu, kind, setting, r, ref, tol=None):
    e_x, e_k = ac.errors(r, ref)
    out = dict(case=case.name, viscosity=mu, kind=kind, setting=setting, tolerance=tol, steps=r['steps'], seconds=r['seconds'],
               error_positions=e_x, error_kinetic=e_k, error_kinetic_sampled=ac.errors(r, ref, sampled=True)[1], error=max(e_x, e_k),
               estimate=r['estimate'], switches=r['switches'],
               stopped=r['why'] or '')
    print('  %-11s %-22s steps %8d  %8.3f s  error %.2e (e_x %.2e, e_K %.2e)%s%s' % (
        kind, setting, r['steps'], r['seconds'], out['error'], e_x, e_k,
        '  estimate %.2e, switches %d' % (r['estimate'], r['switches']) if r['estimate'] is not None else '',
        ('  unstable: ' + r['why'][:50]) if r['why'] else ''))
    sys.stdout.flush()
    return out


def oracle_rows(case, mu, ref, tightest):
    """Fixed settings from the cheapest down, per scheme, until one meets the tightest tolerance or
    halving the step no longer lowers the error by a third (the reference's own error, or a floor
    no step reaches: a smaller step would only cost)."""
    rows = []

    def ladder(runs):
        mine = []
        for kind, setting, run in runs:
            mine.append(row(case, mu, kind, setting, run(), ref))
            if mine[-1]['error'] <= tightest or (len(mine) > 1 and mine[-1]['error'] > (2 / 3) * mine[-2]['error']):
                break
        rows.extend(mine)
    ladder(('explicit', 'stepper safety %g' % safety, lambda safety=safety: ac.run_stepper(case, mu, 'explicit', safety=safety))
           for safety in SAFETIES)
    ladder(('implicit', 'dt %.3g s' % (case.T / ac.SAMPLES / k), lambda k=k: ac.run_fixed(case, mu, 'implicit', k))
           for k in IMPLICIT_K[case.name])
    return rows


def write_keeping_others(path, mine, ran, text_columns):
    """Write the rows `mine` to the CSV at `path` after the rows it holds of the cases not in `ran`."""
    import csv
    kept = []
    if os.path.exists(path):
        with open(path) as fh:
            kept = [{k: (v if k in text_columns or not v else float(v)) for k, v in r.items()}
                    for r in csv.DictReader(fh) if r['case'] not in ran]
    common.write_rows(path, kept + mine)
    return kept + mine


def calibration(cases):
    """True error ÷ errorEstimate of fixed implicit steps (physics.md A4a): what c has to cover."""
    out = []
    for case in cases:
        for mu in VISCOSITIES:
            ref = reference_run(case, mu)[0]  # its own error is not needed here
            for k in CALIBRATION_K.get(case.name, IMPLICIT_K[case.name][:4]):
                dt = case.T / ac.SAMPLES / k
                r = ac.run_stepper(case, mu, 'implicit', max_dt=dt)
                error, sampled = max(ac.errors(r, ref)), max(ac.errors(r, ref, sampled=True))
                out.append(dict(case=case.name, viscosity=mu, dt=dt, steps=r['steps'], error=error, estimate=r['estimate'],
                                ratio=error / r['estimate'], error_sampled=sampled, ratio_sampled=sampled / r['estimate']))
                print('%-11s μ %6g  Δt %.3g s  error %.2e  estimate %.2e  error/estimate %.2f' % (
                    case.name, mu, dt, error, r['estimate'], out[-1]['ratio']))
                sys.stdout.flush()
    path = os.path.join(common.RESULTS, 'accuracy_calibration.csv')
    write_keeping_others(path, out, {c.name for c in cases}, ('case',))


if args.calibration:
    calibration(CASES)
    sys.exit(0)

rows, summary = [], []
for case in ([] if args.replot else CASES):
    for mu in VISCOSITIES:
        ref, ref_error, ref_scheme, ref_dt = reference(case, mu)
        print('\n%s, μ = %g Pa·s: reference %s at dt %.3e s (%d steps; its own error ~%.1e)' % (
            case.name, mu, ref_scheme, ref_dt, ref['steps'], ref_error))
        fixed = oracle_rows(case, mu, ref, min(TOLERANCES))
        rows += fixed
        for tol in TOLERANCES:
            mine = row(case, mu, 'accuracy', 'accuracy=%g' % tol, ac.run_stepper(case, mu, accuracy=tol), ref, tol)
            rows.append(mine)
            best = min((r for r in fixed if r['error'] <= tol), key=lambda r: r['seconds'], default=None)
            summary.append(dict(case=case.name, viscosity=mu, tolerance=tol, reference_error=ref_error,
                                error=mine['error'], estimate=mine['estimate'], seconds=mine['seconds'], steps=mine['steps'],
                                switches=mine['switches'], oracle=best and '%s %s' % (best['kind'], best['setting']),
                                oracle_error=best and best['error'], oracle_seconds=best and best['seconds'],
                                oracle_steps=best and best['steps'],
                                cost_ratio=best and mine['seconds'] / best['seconds'], error_ratio=mine['error'] / tol))

if args.replot:
    import csv
    with open(os.path.join(common.RESULTS, 'accuracy_target_summary.csv')) as fh:
        summary = [{k: (v if k in ('case', 'oracle') or not v else float(v)) for k, v in r.items()} for r in csv.DictReader(fh)]
else:  # the rows of the cases not run this time are kept
    text = ('case', 'oracle', 'kind', 'setting', 'stopped')
    ran = {c.name for c in CASES}
    write_keeping_others(os.path.join(common.RESULTS, 'accuracy_target.csv'), rows, ran, text)
    summary = write_keeping_others(os.path.join(common.RESULTS, 'accuracy_target_summary.csv'), summary, ran, text)  # all cases, for the figure
print('\n%-11s %6s %6s | %9s %9s %8s %7s | %-26s %9s %8s | %6s' % (
    'case', 'μ', 'tol', 'error', 'estimate', 'wall [s]', 'steps', 'oracle', 'error', 'wall [s]', 'cost×'))
for s in summary:
    print('%-11s %6g %6g | %9.2e %9.2e %8.3f %7d | %-26s %9s %8s | %6s' % (
        s['case'], s['viscosity'], s['tolerance'], s['error'], s['estimate'], s['seconds'], s['steps'], s['oracle'] or 'none',
        '%.2e' % s['oracle_error'] if s['oracle'] else '-', '%.3f' % s['oracle_seconds'] if s['oracle'] else '-',
        '%.2f' % s['cost_ratio'] if s['oracle'] else '-'))

# --- figure: achieved error and cost ratio against the tolerance, one line per case and viscosity
def plot(summary, png):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    cases = list(dict.fromkeys(s['case'] for s in summary))
    viscosities = list(dict.fromkeys(s['viscosity'] for s in summary))
    tolerances = sorted({s['tolerance'] for s in summary})
    fig, (ax_e, ax_c) = plt.subplots(1, 2, figsize=(12.5, 4.6))
    for n, case in enumerate(cases):
        for m, mu in enumerate(viscosities):
            mine = [s for s in summary if s['case'] == case and s['viscosity'] == mu]
            if not mine:
                continue
            # a case by its marker and line, a viscosity by its colour: no two series look alike
            style = dict(color='C%d' % m, marker='os^Dvp'[n % 6], ls=('-', '--', ':', '-.', (0, (5, 1, 1, 1, 1, 1)), (0, (1, 1)))[n % 6],
                         label='%s, μ = %g Pa·s' % (case, mu))
            ax_e.loglog([s['tolerance'] for s in mine], [s['error'] for s in mine], **style)
            pts = [(s['tolerance'], s['cost_ratio']) for s in mine if s['cost_ratio']]
            if pts:
                ax_c.loglog(*zip(*pts), **style)
    lims = [min(tolerances) / 3, max(tolerances) * 3]
    ax_e.loglog(lims, lims, color='grey', ls=':', lw=1, label='error = tolerance')
    ax_e.set_xlabel('tolerance (accuracy=...)')
    ax_e.set_ylabel('achieved error against the reference')
    ax_e.set_title('error', fontsize=9)
    ax_c.axhline(2, color='grey', ls=':', lw=1, label='goal: 2× the oracle')
    ax_c.axhline(1, color='grey', lw=0.5)
    ratios = [s['cost_ratio'] for s in summary if s['cost_ratio']] + [1, 2]
    ax_c.set_yticks([t for t in (0.01, 0.03, 0.1, 0.3, 1, 2, 3, 10, 30, 100) if min(ratios) / 2 <= t <= max(ratios) * 2])
    ax_c.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter('%g'))
    ax_c.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax_c.set_xlabel('tolerance (accuracy=...)')
    ax_c.set_ylabel('wall time / the oracle\'s')
    ax_c.set_title('cost against the cheapest fixed setting that meets the tolerance', fontsize=9)
    for a in (ax_e, ax_c):
        a.grid(True, which='both', alpha=0.3)
    # one legend for both panels, beside them: inside, it hid the points it names
    handles, labels = ax_e.get_legend_handles_labels()
    goal = [(h, lab) for h, lab in zip(*ax_c.get_legend_handles_labels()) if lab.startswith('goal')]
    fig.legend(handles + [h for h, _ in goal], labels + [lab for _, lab in goal], loc='center right', fontsize=7, frameon=False)
    fig.suptitle('Accuracy as the input (viscbridge.engines(accuracy=...)): achieved error and cost')
    fig.tight_layout(rect=(0, 0, 0.82, 1))
    fig.savefig(png, dpi=110)


png = os.path.join(common.RESULTS, 'accuracy_target.png')
plot(summary, png)
print('\nwritten', png if args.replot else '%s %s' % (os.path.join(common.RESULTS, 'accuracy_target.csv'), png))
