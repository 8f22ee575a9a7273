"""viscbridge.scan: the instability criterion, the bisection, case checks, resuming, the yade-batch
route and the command line (errors, Ctrl-C, failed cases, help)."""
import argparse
import hashlib
import json
import math
import os
import pathlib
import re
import signal
import subprocess
import sys
import time

import pytest

import viscbridge.criteria as criteria
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
    with pytest.raises(ValueError, match='viscosty'):
        scan.one_at_a_time({}, viscosty=[])


def test_numbers_take_the_type_of_their_default_so_equal_cases_run_once():
    c = scan.normalize_case(dict(n=20.0, seed=3.0, viscosity=1, young=10**7))
    assert (type(c['n']), type(c['seed']), type(c['viscosity']), type(c['young'])) == (int, int, float, float)
    numpy = pytest.importorskip('numpy')
    c = scan.normalize_case(dict(n=numpy.int64(20), viscosity=numpy.float32(2)))
    assert (type(c['n']), type(c['viscosity'])) == (int, float) and scan.case_key(c) == scan.case_key(dict(n=20, viscosity=2))
    assert scan.case_key(dict(viscosity=1)) == scan.case_key(dict(viscosity=1.0))
    assert len(scan.one_at_a_time({}, viscosity=[1, 1.0, 2, 2])) == 2  # the base has viscosity 1.0
    assert len(scan.grid(viscosity=[1, 1.0], n=[20, 20.0])) == 1
    assert len(scan.unique_cases([dict(n=20), dict(n=20.0), dict(n=21)])) == 2
    # a scan written before keeps its keys, so that it resumes (fields added since, like the capillary
    # ones, are left out of the key at their defaults): the defaults' key of docs/data's scans
    assert scan.case_key({}) == '9e1baa0e9261c915'
    assert scan.case_key(dict(capillaryModel='willett', surfaceTension=0.05)) != scan.case_key({})


@pytest.mark.parametrize('field, value', [
    ('n', 0), ('n', 2.5), ('n', True), ('n', '20'), ('seed', 1.5), ('steps', 0), ('radius', 0.0), ('radius', float('nan')),
    ('sizeRatio', 6.0), ('density', -1.0), ('young', float('inf')), ('poisson', 0.5), ('friction', -0.1),
    ('viscosity', -1.0), ('viscosity', '1'), ('sMinRel', 0.0), ('sMinRel', 1.5), ('bridgeVolumeRel', 0.0),
    ('contactAngle', 2.0), ('en', 0.0), ('en', 1.5), ('perturbation', -0.01), ('tolerance', 0.0),
    ('normalModel', 'foo'), ('tangentialModel', 'foo'), ('tangentialModel', 1), ('integration', 'semi')])
def test_values_out_of_range_are_rejected_naming_the_field(field, value):
    with pytest.raises(ValueError, match=r'scan case: %s=.* is out of range; allowed: ' % field):
        scan.normalize_case({field: value})


def test_allowed_values_are_those_of_the_ip2():
    """Model names come from viscbridge.criteria (as ModelNames.hpp); the liquid ranges agree with
    what the C++ functor accepts, probed at and around their ends."""
    import yade.wrapper as yw
    assert scan.CASE_FIELDS['normalModel'].allowed is criteria.NORMAL_MODELS
    assert scan.CASE_FIELDS['tangentialModel'].allowed is criteria.TANGENTIAL_MODELS
    assert scan.CASE_FIELDS['integration'].allowed is criteria.INTEGRATIONS
    assert set(scan.CASE_FIELDS) == set(scan.CASE_DEFAULTS)

    def ip2_accepts(**kw):
        try:
            yw.Ip2_FrictMat_FrictMat_ViscBridgePhys(**kw)
            return True
        except ValueError:
            return False
    for field in ('normalModel', 'tangentialModel'):
        for name in scan.CASE_FIELDS[field].allowed + ('foo',):
            assert ip2_accepts(**{field: name}) == (name in scan.CASE_FIELDS[field].allowed)
    for field in ('viscosity', 'sMinRel', 'bridgeVolumeRel', 'contactAngle', 'en'):
        for v in (-1.0, 0.0, 1e-9, 0.5, 1.0, 1.5, math.pi / 2, math.pi / 2 + 1e-9, 2.0):
            assert ip2_accepts(**{field: v}) == (v in scan.CASE_FIELDS[field].allowed), (field, v)


def test_case_failures_are_read_from_the_case_logs(tmp_path):
    a, b, c = [scan.normalize_case(dict(viscosity=v)) for v in (1.0, 2.0, 3.0)]
    key = scan.case_key
    (tmp_path / ('case-%s.log' % key(a))).write_text('Running script\nTraceback (most recent call last):\n'
                                                    '  File "x.py", line 1\nValueError: planted\nYade: bye\n')
    (tmp_path / ('case-%s.log' % key(c))).write_text('Running script\nSegmentation fault\n')
    failed = {key(case): error for case, error in scan._failures([a, b, c], {key(c)}, {key(c)}, str(tmp_path))}
    assert failed[key(a)] == 'ValueError: planted'                        # no result line
    assert failed[key(b)].startswith('not started')                      # no result, no log
    assert failed[key(c)] == 'wrote its result, then failed: Segmentation fault'  # reported FAILED
    message = str(scan.CasesFailed([(a, failed[key(a)]), (b, failed[key(b)])], str(tmp_path)))
    assert message.startswith('2 case(s) failed') and key(a) in message and 'viscosity=2.0' in message


# --- the command line ----------------------------------------------------------------------------
def scan_cli(*args):
    """`python3 -m viscbridge.scan ARGS` in plain Python (no YADE): (exit status, stdout, stderr)."""
    p = subprocess.run([sys.executable, '-m', 'viscbridge.scan', *args], capture_output=True, text=True, timeout=300)
    return p.returncode, p.stdout, p.stderr


def assignments(case):
    return ['%s=%s' % (k, json.dumps(v)) for k, v in case.items()]


@pytest.mark.parametrize('args, says', [
    (['run', '{new}', '--base', 'tangentialModel=foo'], "tangentialModel='foo' is out of range; allowed: 'none', 'washino'"),
    (['run', '{new}', '--vary', 'viscosity=1,-1'], 'viscosity=-1 is out of range'),
    (['run', '{new}', '--base', 'n=abc'], "n='abc' is out of range; allowed: an integer >= 1"),
    (['run', '{new}', '-j', '0'], 'jobs=0'),
    (['table', '{new}', '--base', 'n=2.5'], 'n=2.5 is out of range'),
    (['table', '{new}', '--vary', 'viscosty=1,2'], 'unknown field(s) viscosty'),
    (['table', '{new}', '--base', 'viscosity'], "expected FIELD=VALUE, got 'viscosity'"),
    (['collect', '{new}'], 'no such scan directory'),
    (['slurm', '{new}'], 'no such scan directory'),
    (['collect', '{empty}'], 'no finished case'),
    (['slurm', '{empty}'], 'cases.table'),
])
def test_errors_are_one_line_and_a_non_zero_status(tmp_path, args, says):
    new, empty = tmp_path / 'new', tmp_path / 'empty'
    empty.mkdir()
    status, out, err = scan_cli(*[a.format(new=new, empty=empty) for a in args])
    assert status == 1 and out == ''
    assert len(err.strip().splitlines()) == 1 and err.startswith('scan: error: ') and says in err, err
    assert not new.exists()  # checked before anything is written or launched


def test_table_checks_every_case_before_writing_and_drops_duplicates(tmp_path):
    status, out, err = scan_cli('table', str(tmp_path), '--vary', 'viscosity=1,1.0,2', 'n=20,20.0')
    assert status == 0, err
    table = (tmp_path / 'cases.table').read_text()
    assert len(table.splitlines()) == 1 + 3  # base, viscosity=2, n=20
    status, out, err = scan_cli('table', str(tmp_path), '--vary', 'viscosity=3,-1')
    assert status == 1 and 'viscosity=-1' in err
    assert (tmp_path / 'cases.table').read_text() == table
    assert sorted(p.name for p in tmp_path.iterdir()) == ['cases.table']


def test_help_lists_every_field_with_default_and_unit_and_every_option():
    for command in ([], ['run'], ['table']):
        status, out, err = scan_cli(*command, '--help')
        assert status == 0
        for name, default in scan.CASE_DEFAULTS.items():
            shown = '%g' % default if isinstance(default, float) else str(default)
            unit = scan.CASE_FIELDS[name].unit or '-'
            assert re.search(r'^  %s +%s +%s +\S' % (name, re.escape(shown), re.escape(unit)), out, re.M), (command, name)
    parser = scan.build_parser()
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert {a.dest for a in commands._choices_actions if a.help} == {'run', 'table', 'collect', 'slurm'}
    for name, sub in commands.choices.items():
        assert all(a.help for a in sub._actions), name


def test_keyboard_interrupt_is_one_line(tmp_path, monkeypatch, capsys):
    def interrupted(scan_dir):
        raise KeyboardInterrupt
    monkeypatch.setattr(scan, 'collect', interrupted)
    assert scan.main(['collect', str(tmp_path)]) == 130
    assert capsys.readouterr().err == 'scan: interrupted\n'


# --- parallel runs through yade-batch, results, resuming -----------------------------------------
def scan_cases():
    return scan.one_at_a_time(dict(TINY, viscosity=10.0), viscosity=[30.0, 100.0])


def results_of(scan_dir):
    return scan.ResultsFile(os.path.join(scan_dir, 'results.jsonl')).read()  # a line being written is left out


def test_yade_batch_runs_the_table_and_results_are_collected(tmp_path):
    rows = scan.run_cases(scan_cases()[:2], str(tmp_path), jobs=2, progress=False)
    assert sorted(r['viscosity'] for r in rows) == [10.0, 30.0]
    for r in rows:
        assert r['dt_stable'] < r['dt_critical'] < r['dt_unstable'] <= r['dt_stable'] * 1.2 * (1 + 1e-12)
        assert r['governing'] == 'viscous-network'
    # Δt_crit ∝ 1/μ once viscous forces dominate: ×3 viscosity, ÷3 step (within the bracket width)
    by_mu = {r['viscosity']: r['dt_critical'] for r in rows}
    assert by_mu[10.0] / by_mu[30.0] == pytest.approx(3.0, rel=0.25)
    for name in ('cases.table', 'todo.table'):
        table = open(tmp_path / name).read().splitlines()
        assert len(table) == 3 and table[0].split()[0] == 'description'
    collected = scan.collect(str(tmp_path))
    assert len(collected) == 2 and os.path.exists(tmp_path / 'results.csv')
    # each case's log is kept with the scan, none is written into the package
    assert len(list(tmp_path.glob('case-*.log'))) == 2
    assert not list(pathlib.Path(scan.JOB_SCRIPT).parent.glob('*.log'))
    # the job script skips a case already done, so that resubmitting a Slurm array is cheap
    env = dict(os.environ, YADE_BATCH='%s:2' % (tmp_path / 'cases.table'))
    job = subprocess.run(['yade', '-n', '-x', scan.JOB_SCRIPT], env=env, capture_output=True, text=True, timeout=300)
    assert job.returncode == 0 and 'skipped' in job.stdout, job.stdout + job.stderr
    assert len(results_of(tmp_path)) == 2


def test_a_case_failing_at_run_time_fails_the_scan_with_its_error(tmp_path):
    """Valid fields, but the implicit solver refuses the non-dissipative washino model at the first
    step: the scan exits non-zero and lists the case with the error from its log."""
    failing = dict(TINY, n=20, viscosity=10.0, integration='implicit', tangentialModel='washino')
    status, out, err = scan_cli('run', str(tmp_path), '-j', '1', '--base', *assignments(failing))
    assert status == 1 and 'Traceback' not in err, err
    assert 'scan: error: 1 case(s) failed' in err
    line = next(line for line in err.splitlines() if scan.case_key(failing) in line)
    assert "tangentialModel='washino'" in line and 'not dissipative' in line
    assert results_of(tmp_path) == []


def processes():
    """(pid, parent pid, process group, state) of every process."""
    out = []
    for pid in filter(str.isdigit, os.listdir('/proc')):
        try:
            with open('/proc/%s/stat' % pid) as fh:
                fields = fh.read().rsplit(')', 1)[1].split()
        except OSError:
            continue  # ended meanwhile
        out.append((int(pid), int(fields[1]), int(fields[2]), fields[0]))
    return out


def live_members(group):
    return [pid for pid, _, g, state in processes() if g == group and state != 'Z']


def wait_for(condition, timeout, what):
    deadline = time.time() + timeout
    while not condition():
        assert time.time() < deadline, 'timed out waiting for ' + what
        time.sleep(0.2)


def start_scan(*args):
    """The scan command line as a separate driver; SIGINT at its default, as in a terminal (a
    background test runner may have it ignored).  Returns the driver and its yade-batch's group."""
    def default_sigint():
        signal.signal(signal.SIGINT, signal.SIG_DFL)
    proc = subprocess.Popen([sys.executable, '-m', 'viscbridge.scan', *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True, preexec_fn=default_sigint)
    found = []
    wait_for(lambda: found.extend(p for p, parent, g, _ in processes() if parent == proc.pid and g == p) or found,
             60, 'yade-batch in a session of its own')
    return proc, found[0]


def stop_scan(proc, batch):
    """After a failed test: nothing is left running."""
    for group in (proc.pid, batch):
        try:
            os.killpg(group, signal.SIGKILL)
        except ProcessLookupError:
            pass
    proc.wait()


def interrupted(proc, batch, sig):
    """Send `sig` to the driver only; its exit status and stderr, once yade-batch's group is gone."""
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=120)
    wait_for(lambda: not live_members(batch), 15, 'yade-batch and its jobs to end')
    return proc.returncode, err


def test_sigterm_stops_yade_batch_and_its_job(tmp_path):
    earlier = {'key': 'written-before', 'dt_critical': 1.0}
    scan.ResultsFile(str(tmp_path / 'results.jsonl')).append(earlier)
    proc, batch = start_scan('run', str(tmp_path), '-j', '1', '--base', *assignments(dict(TINY, viscosity=10.0)))
    try:
        wait_for(lambda: list(tmp_path.glob('case-*.log')) and len(live_members(batch)) >= 2, 120, 'the job')
        status, err = interrupted(proc, batch, signal.SIGTERM)
    finally:
        stop_scan(proc, batch)
    assert status == 130 and 'Traceback' not in err
    message = [line for line in err.splitlines() if 'interrupted' in line]
    assert len(message) == 1 and 'run the same command again to resume' in message[0], err
    assert results_of(tmp_path) == [earlier]


def test_an_interrupted_scan_resumes_without_repeating_finished_cases(tmp_path):
    """Ctrl-C (SIGINT to the driver only, as a terminal does: yade-batch is in a session of its own)
    once a case has finished: yade-batch and its job end, the finished case stays, and the next run
    does the rest; the Slurm script still covers the whole scan."""
    cli = ['run', str(tmp_path), '-j', '1', '--base', *assignments(dict(TINY, viscosity=10.0)), '--vary', 'viscosity=30,100']
    proc, batch = start_scan(*cli)
    try:
        wait_for(lambda: results_of(tmp_path) and len(live_members(batch)) >= 2, 300, 'the first result')
        status, err = interrupted(proc, batch, signal.SIGINT)
    finally:
        stop_scan(proc, batch)
    assert status == 130 and 'Traceback' not in err
    assert any('interrupted' in line and 'resume' in line for line in err.splitlines()), err
    first = results_of(tmp_path)
    assert 1 <= len(first) < 3, 'the interruption should have landed mid-scan'
    # the same scan again, with a case repeated as an integer: it runs once
    rows = scan.run_cases(scan_cases() + [dict(TINY, viscosity=30)], str(tmp_path), jobs=2, progress=False)
    keys = [r['key'] for r in rows]
    assert sorted(keys) == sorted(scan.case_key(c) for c in scan_cases())  # every case, each once
    assert all(r in rows for r in first)  # finished cases were kept, not rerun
    assert len(open(tmp_path / 'todo.table').read().splitlines()[1:]) == 3 - len(first)
    assert len(open(tmp_path / 'cases.table').read().splitlines()[1:]) == 3
    sbatch = open(scan.slurm_script(str(tmp_path))).read()
    assert '#SBATCH --array=2-4' in sbatch and str(tmp_path / 'cases.table') in sbatch
