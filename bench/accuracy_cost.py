# What accuracy costs: error against wall-clock time and against steps, explicit vs implicit.
#
#   ./yadew run bench/accuracy_cost.py [MU ...]      (default: 1 10 100 1000 Pa·s; ~15 min)
#
# The case: a bed of 45 spheres (r = 0.5 mm, 2500 kg/m³, E = 10 MPa) settled dry in a narrow walled
# column, then wetted (every contact a bridge, Adams–Perchard + slip, S_min = 1e-3 r̄) and given
# random velocities of up to 1 cm/s — the trial of the critical-Δt scans (viscbridge.scan), the
# viscosity-dominated regime where the explicit step collapses.  It is followed for T = 1e-4 s.
#
# Stability: the scans' criterion (viscbridge.scenes.instability: kinetic energy above the released
# potential energy plus the initial kinetic energy, or not finite), checked at every sample.
#
# Error measures, each relative to a reference run (explicit at a quarter of the stepper's limit):
#   e_x  RMS over the spheres of |x(T) - x_ref(T)|, divided by the RMS displacement of the
#        reference over the run: how wrong the end state is, on the scale of how much it moved.
#   e_K  sum over the 10 sample times (every T/10) of |K - K_ref|, divided by the sum of K_ref:
#        how wrong the kinetic-energy history is.  Every run's Δt divides T/10, so the samples
#        fall on the same instants.
#   error = max(e_x, e_K); "meets 1 %" means error <= 0.01.
# The reference's own error is estimated by the explicit run at twice its step (first order: its
# error is about the reference's).  Cost: steps, and wall-clock time of the engines (YADE's
# per-engine timers, so the 40 ms polling of O.run(n, True) is not counted).
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # yade -x: __file__ is yade's own
import accuracy_case as ac  # noqa: E402
import common  # noqa: E402
from yade import O  # noqa: E402
import yade.wrapper as yw  # noqa: E402

CASE = ac.Bed45()
T, SAMPLES = CASE.T, ac.SAMPLES
TAU = T / SAMPLES
EXPLICIT_FACTORS = [0.5, 1, 2, 4, 8, 16]           # × the stepper's limit (safety 1)
IMPLICIT_STEPS_PER_SAMPLE = [2, 4, 16, 64, 256, 1024, 4096]  # Δt = T/10/k; k = 2 is 5e-6 s
TIGHT = 1e-12  # CG tolerance of the twin of each implicit run: what the default tolerance adds

viscosities = [float(a) for a in sys.argv[1:]] or [1.0, 10.0, 100.0, 1000.0]


def stepper_limits(mu):
    """(combined, collision) limit of ViscBridgeTimeStepper at safety 1 on the wetted bed [s]: the
    spectral limit of the network (physics.md P18), 2.6× its rigorous floor P14 here."""
    CASE.prepare(mu, 'explicit', stepper=True, safety=1.0)
    O.dt = 1e-12
    O.run(2, True)
    ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
    return ts.dtBound, ts.dtCollision


def run(mu, integration, k, tolerance=None):
    return ac.run_fixed(CASE, mu, integration, k, tolerance)


errors = ac.errors


def steps_for(dt):
    return max(1, int(round(TAU / dt)))


def row(mu, integration, role, k, r, ref, tight=None):
    """The row of run r against the reference; with `tight` (the same run solved to TIGHT), also the
    error the solver's default tolerance adds (the same measure, against the tight run)."""
    e_x, e_k = errors(r, ref)
    out = dict(viscosity=mu, integration=integration, role=role, dt=TAU / k, steps=SAMPLES * k, executed_steps=r['steps'],
               seconds=r['seconds'], error_positions=e_x, error_kinetic=e_k, error_kinetic_sampled=errors(r, ref, sampled=True)[1], error=max(e_x, e_k),
               cg_iterations_per_step=r['cg'], stopped=r['why'] or '',
               error_from_tolerance=max(errors(r, tight)) if tight else None)
    print('  %-8s %-9s dt %.3e s  steps %9d  %8.2f s  e_x %.2e  e_K %.2e  %s%s' % (
        integration, role, out['dt'], out['steps'], out['seconds'], e_x, e_k, ('unstable: ' + r['why'][:60]) if r['why'] else '',
        ('  from the tolerance %.1e' % out['error_from_tolerance']) if tight else ''))
    sys.stdout.flush()
    return out


rows, summary = [], []
for mu in viscosities:
    bound, collision = stepper_limits(mu)
    print('\nμ = %g Pa·s: stepper limit %.3e s (collision part %.3e s), reference Δt = limit/4' % (mu, bound, collision))
    k_ref = steps_for(0.25 * bound)
    ref = run(mu, 'explicit', k_ref)
    assert not ref['why'], ref['why']
    rows.append(row(mu, 'explicit', 'reference', k_ref, ref, ref))
    ladder = {}
    for f in EXPLICIT_FACTORS:
        k = steps_for(f * bound)
        if k in ladder or k == k_ref:
            continue
        ladder[k] = run(mu, 'explicit', k)
        rows.append(row(mu, 'explicit', 'ladder', k, ladder[k], ref))
        if ladder[k]['why']:
            break
    # the explicit critical step: bisection (to 5 %) between the largest stable and the smallest
    # unstable rung; the largest stable Δt found is reported
    stable = min(k for k, r in ladder.items() if not r['why'])
    unstable = max((k for k, r in ladder.items() if r['why']), default=None)
    while unstable is not None and stable / unstable > 1.05:
        k = steps_for(TAU / math.sqrt(stable * unstable))
        if k in (stable, unstable):
            break
        ladder[k] = run(mu, 'explicit', k)
        if ladder[k]['why']:
            unstable = k
        else:
            stable = k
    if unstable is not None:
        rows.append(row(mu, 'explicit', 'critical', stable, ladder[stable], ref))
    for k in IMPLICIT_STEPS_PER_SAMPLE:
        rows.append(row(mu, 'implicit', 'ladder', k, run(mu, 'implicit', k), ref, tight=run(mu, 'implicit', k, TIGHT)))
    mine = [r for r in rows if r['viscosity'] == mu]
    floor = next(r['error'] for r in mine if r['integration'] == 'explicit' and r['role'] == 'ladder' and not r['stopped'])
    for scheme in ('explicit', 'implicit'):
        good = [r for r in mine if r['integration'] == scheme and r['role'] != 'reference' and r['error'] <= 0.01]
        best = min(good, key=lambda r: r['seconds'], default=None)
        crit = next((r for r in mine if r['role'] == 'critical'), None)
        summary.append(dict(viscosity=mu, integration=scheme, bound=bound, reference_error=floor,
                            cheapest_dt=best and best['dt'], cheapest_steps=best and best['steps'],
                            cheapest_seconds=best and best['seconds'], cheapest_error=best and best['error'],
                            explicit_critical_dt=crit and crit['dt'], explicit_critical_steps=crit and crit['steps'],
                            explicit_critical_seconds=crit and crit['seconds']))

common.write_rows(os.path.join(common.RESULTS, 'accuracy_cost.csv'), rows)
common.write_rows(os.path.join(common.RESULTS, 'accuracy_cost_summary.csv'), summary)

print('\nCheapest setting with error <= 1 %% over T = %g s (45 spheres, %d thread(s))' % (T, O.numThreads))
print('%8s %-9s %11s %10s %10s %9s | %-33s' % ('μ', 'scheme', 'dt [s]', 'steps', 'wall [s]', 'error', 'explicit at its critical dt'))
for s in summary:
    crit = ('%.3e s, %d steps, %.2f s' % (s['explicit_critical_dt'], s['explicit_critical_steps'], s['explicit_critical_seconds'])
            if s['explicit_critical_dt'] else '-')
    if s['cheapest_dt'] is None:
        print('%8g %-9s %11s' % (s['viscosity'], s['integration'], 'none'))
    else:
        print('%8g %-9s %11.3e %10d %10.3f %9.2e | %s' % (s['viscosity'], s['integration'], s['cheapest_dt'], s['cheapest_steps'],
                                                         s['cheapest_seconds'], s['cheapest_error'], crit))

# --- figure: error against wall-clock time and against steps, one curve per scheme, per viscosity
import matplotlib  # noqa: E402
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

fig, axes = plt.subplots(2, len(viscosities), figsize=(3.6 * len(viscosities), 6.4), squeeze=False)
for col, mu in enumerate(viscosities):
    for line, (x_key, x_label) in enumerate((('seconds', 'wall-clock time [s]'), ('steps', 'steps'))):
        ax = axes[line][col]
        for scheme, style in (('explicit', 'o-'), ('implicit', 's-')):
            pts = sorted((r[x_key], r['error']) for r in rows if r['viscosity'] == mu and r['integration'] == scheme
                         and r['role'] != 'reference' and math.isfinite(r['error']))
            if pts:
                ax.loglog(*zip(*pts), style, label=scheme)
            crit = [r for r in rows if r['viscosity'] == mu and r['role'] == 'critical']
            if scheme == 'explicit' and crit:
                ax.axvline(crit[0][x_key], color='C0', ls=':', lw=1, label='explicit at its critical Δt')
        ax.axhline(0.01, color='grey', ls='--', lw=1)
        ax.set_xlabel(x_label)
        if col == 0:
            ax.set_ylabel('error (max of e_x, e_K)')
        if line == 0:
            ax.set_title('μ = %g Pa·s' % mu)
        ax.legend(fontsize=7)
fig.suptitle('Accuracy against cost: wetted 45-sphere bed, T = %g s' % T)
fig.tight_layout()
png = os.path.join(common.RESULTS, 'accuracy_cost.png')
fig.savefig(png, dpi=110)
print('\nwritten', os.path.join(common.RESULTS, 'accuracy_cost.csv'), png)
