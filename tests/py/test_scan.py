"""viscbridge.scan: the instability criterion, the bisection, resuming and the yade-batch route."""
import json
import math
import os
import pathlib
import signal
import subprocess
import sys
import time

import pytest

import viscbridge.scan as scan
from viscbridge.scenes import instability

TINY = dict(n=40, steps=300, tolerance=0.2, seed=2)


# --- the criterion -------------------------------------------------------------------------------
def test_criterion_on_numbers():
    assert instability(1.0, 2.0) is None                      # dissipated part of what was released
    assert instability(1.0, 0.5, initial_kinetic=0.6) is None  # initial motion counts
    assert 'exceeds' in instability(2.1, 2.0)
    assert 'non-finite' in instability(float('nan'), 1.0)
    assert 'non-finite' in instability(1.0, float('inf'))


@pytest.fixture(scope='module')
def bed_dir(tmp_path_factory):
    return str(tmp_path_factory.mktemp('beds'))


def test_criterion_classifies_known_runs(bed_dir):
    """Wetted bed: stable at half the time stepper's step, unstable at 3× the pair limit 2 t_v."""
    case = scan.normalize_case(dict(TINY, viscosity=10.0))
    trial = scan._Trial(case, scan.dry_bed(case, bed_dir))
    dt_stepper = trial.stepper_dt()['dt_stepper']
    assert trial.unstable_at(0.5 * dt_stepper) is None
    t_v = 4.0 / 9.0 * 2500 * 0.5e-3 * (1e-3 * 0.25e-3) / 10.0
    why = trial.unstable_at(3 * 2 * t_v)
    assert why and ('exceeds' in why or 'non-finite' in why)


# --- bisection -----------------------------------------------------------------------------------
@pytest.mark.parametrize('guess', [(1.0, 2.0), (5.0, 9.0), (0.01, 0.02), (30.0, 300.0)])
def test_bisection_brackets_a_planted_threshold(guess):
    threshold = 3.7
    lo, hi, trials = scan.bisect_threshold(lambda x: x >= threshold, *guess, tolerance=0.01)
    assert lo < threshold <= hi and hi / lo <= 1.01
    assert all((x >= threshold) == u for x, u in trials)
    assert len(trials) < 40


def test_bisection_rejects_bad_input():
    with pytest.raises(ValueError, match='lo'):
        scan.bisect_threshold(lambda x: True, 2.0, 1.0)
    with pytest.raises(ValueError, match='tolerance'):
        scan.bisect_threshold(lambda x: True, 1.0, 2.0, tolerance=0)


def test_cases_and_keys():
    cases = scan.one_at_a_time(dict(viscosity=1.0), viscosity=[1.0, 10.0], sMinRel=[1e-2])
    assert [c['viscosity'] for c in cases] == [1.0, 10.0, 1.0] and cases[2]['sMinRel'] == 1e-2
    assert len({scan.case_key(c) for c in cases}) == 3
    assert scan.case_key(dict(viscosity=1.0)) == scan.case_key(dict(viscosity=1.0, n=300))  # defaults
    assert len(scan.grid(viscosity=[1, 2], sMinRel=[1e-3, 1e-2])) == 4
    with pytest.raises(ValueError, match='viscosty'):
        scan.normalize_case(dict(viscosty=1.0))


# --- parallel runs through yade-batch, results, resuming -----------------------------------------
def scan_cases():
    return scan.one_at_a_time(dict(TINY, viscosity=10.0), viscosity=[30.0, 100.0])


def test_yade_batch_runs_the_table_and_results_are_collected(tmp_path):
    rows = scan.run_cases(scan_cases()[:2], str(tmp_path), jobs=2, progress=False)
    assert sorted(r['viscosity'] for r in rows) == [10.0, 30.0]
    for r in rows:
        assert r['dt_stable'] < r['dt_critical'] < r['dt_unstable'] <= r['dt_stable'] * 1.2 * (1 + 1e-12)
        assert r['governing'] == 'viscous'
    # Δt_crit ∝ 1/μ once viscous forces dominate: ×3 viscosity, ÷3 step (within the bracket width)
    by_mu = {r['viscosity']: r['dt_critical'] for r in rows}
    assert by_mu[10.0] / by_mu[30.0] == pytest.approx(3.0, rel=0.25)
    table = open(tmp_path / 'cases.table').read().splitlines()
    assert len(table) == 3 and table[0].split()[0] == 'description'
    collected = scan.collect(str(tmp_path))
    assert len(collected) == 2 and os.path.exists(tmp_path / 'results.csv')
    # each case's log is kept with the scan, none is written into the package
    assert len(list(tmp_path.glob('case-*.log'))) == 2
    assert not list(pathlib.Path(scan.JOB_SCRIPT).parent.glob('*.log'))


def test_a_killed_scan_resumes_without_repeating_finished_cases(tmp_path):
    results = tmp_path / 'results.jsonl'
    code = ('import viscbridge.scan as s, json, sys; '
            's.run_cases([s.normalize_case(c) for c in json.loads(sys.argv[1])], sys.argv[2], jobs=1, progress=False)')
    proc = subprocess.Popen([sys.executable, '-c', code, json.dumps(scan_cases()), str(tmp_path)], start_new_session=True)
    deadline = time.time() + 300
    while time.time() < deadline and (not results.exists() or len(results.read_text().splitlines()) < 1):
        time.sleep(0.5)
    os.killpg(proc.pid, signal.SIGKILL)  # the whole scan: driver, yade-batch and its job
    proc.wait()
    first = [json.loads(line) for line in results.read_text().splitlines()]
    assert 1 <= len(first) < 3, 'the kill should have landed mid-scan'
    rows = scan.run_cases(scan_cases(), str(tmp_path), jobs=2, progress=False)
    keys = [r['key'] for r in rows]
    assert sorted(keys) == sorted(scan.case_key(c) for c in scan_cases())  # every case, each once
    assert all(r in rows for r in first)  # finished cases were kept, not rerun
    second_table = open(tmp_path / 'cases.table').read().splitlines()[1:]
    assert len(second_table) == 3 - len(first)
