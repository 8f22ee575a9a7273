"""viscbridge.scan without YADE: the bisection, case checks and keys, failed cases read from their
logs, argument checks and a Ctrl-C in the command line.  (Inside YADE: tests/yade/test_scan_yade.py;
the command line and yade-batch runs: tests/system/test_scan_cli.py.)"""
import pytest

import viscbridge.scan as scan


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


def test_keyboard_interrupt_is_one_line(tmp_path, monkeypatch, capsys):
    def interrupted(scan_dir):
        raise KeyboardInterrupt
    monkeypatch.setattr(scan.cli, 'collect', interrupted)  # what the command calls
    assert scan.main(['collect', str(tmp_path)]) == 130
    assert capsys.readouterr().err == 'scan: interrupted\n'


# --- argument checks ------------------------------------------------------------------------------


@pytest.mark.parametrize('kw,name', [
    (dict(n=0), 'n'), (dict(n=2.5), 'n'), (dict(steps=0), 'steps'), (dict(tolerance=0), 'tolerance'),
    (dict(perturbation=-1), 'perturbation'), (dict(viscosity=-1), 'viscosity'), (dict(radius=0), 'radius'),
    (dict(sizeRatio=0.5), 'sizeRatio'), (dict(integration='rk4'), 'integration'), (dict(colour=1), 'colour'),
])
def test_scan_case_fields(kw, name):
    with pytest.raises(ValueError, match=name):
        scan.normalize_case(kw)


def test_scan_jobs(tmp_path):
    with pytest.raises(ValueError, match='jobs'):
        scan.run_cases([], str(tmp_path), jobs=0)


@pytest.mark.parametrize('sig', ['SIGTERM', 'SIGHUP'])
def test_a_signal_after_the_batch_ended_is_reported_not_fatal(tmp_path, sig):
    """`scan run` once died without a word when SIGTERM arrived just after yade-batch ended (its
    handler covered only the wait for yade-batch; collecting the results ran with the default,
    fatal action).  The whole command is interruptible now: the signal is reported, status 130."""
    import subprocess
    import sys
    snippet = (
        'import os, signal, sys\n'
        'import viscbridge.scan.cli as cli\n'
        'def finished_then_signalled(cases, scan_dir, jobs):\n'
        '    os.makedirs(scan_dir, exist_ok=True)\n'
        '    os.kill(os.getpid(), signal.%s)\n'
        '    return []\n'
        'cli.run_cases = finished_then_signalled\n'
        'sys.exit(cli.main(["run", sys.argv[1], "--vary", "viscosity=1"]))\n' % sig)
    proc = subprocess.run([sys.executable, '-c', snippet, str(tmp_path / 'scan')], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 130, (proc.returncode, proc.stderr)
    assert 'scan: interrupted' in proc.stderr and 'Traceback' not in proc.stderr
