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
    (tmp_path / ('case-%s.log' % key(c))).write_text('Running script\nSegmentation fault\n\n=== JOB SUMMARY ===\n'
                                                    'status  : 35584 (FAILED)\nfinished: Mon Dec  7 21:16:09 2026\n')
    failed = {key(case): error for case, error in scan._failures([a, b, c], {key(c)}, {key(c)}, str(tmp_path))}
    assert failed[key(a)] == 'ValueError: planted'                        # no result line
    assert failed[key(b)].startswith('not started')                      # no result, no log
    assert failed[key(c)] == ('wrote its result, then failed: Segmentation fault (no error in its log; '
                              'yade-batch status 35584 (FAILED))')  # reported FAILED
    message = str(scan.CasesFailed([(a, failed[key(a)]), (b, failed[key(b)])], str(tmp_path)))
    assert message.startswith('2 case(s) failed') and key(a) in message and 'viscosity=2.0' in message


def test_an_engine_error_yade_did_not_pass_on_is_read_from_its_fatal_message(tmp_path):
    """YADE's O.wait() can miss an exception thrown at the first step: the log then has only YADE's
    FATAL line with the message on the next line, and yade-batch's job summary after it."""
    case = scan.normalize_case(dict(viscosity=1.0))
    (tmp_path / ('case-%s.log' % scan.case_key(case))).write_text(
        'Running script job.py\n<FATAL ERROR> ThreadRunner:35 void yade::ThreadRunner::run(): Exception occured: \n'
        "Ip2.tangentialModel='washino' is not dissipative\n\n=================== JOB SUMMARY ================\n"
        'status  : 0 (OK)\nfinished: Mon Dec  7 21:16:09 2026\n')
    [(_, error)] = scan._failures([case], set(), set(), str(tmp_path))
    assert error == "Ip2.tangentialModel='washino' is not dissipative"

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


# --- drum cases -----------------------------------------------------------------------------------

DRUM = dict(kind='drum')


def test_a_drum_case_has_its_own_fields_defaults_and_key():
    c = scan.normalize_case(dict(DRUM, viscosity=5, n=40.0))
    assert c['kind'] == 'drum' and set(c) == {'kind'} | set(scan.DRUM_DEFAULTS)
    assert (type(c['viscosity']), type(c['n']), c['revolutions']) == (float, int, scan.DRUM_DEFAULTS['revolutions'])
    assert 'steps' not in c and 'sMinRel' not in c  # a settling trial's fields are not a drum's
    assert scan.case_key(c) == scan.case_key(dict(DRUM, viscosity=5.0, n=40))
    # drum and settling cases with the same values never share a key (resuming compares keys)
    assert scan.case_key(DRUM) != scan.case_key({}) == scan.case_key(dict(kind='settling')) == '9e1baa0e9261c915'
    assert 'kind' not in scan.normalize_case(dict(kind='settling'))  # settling cases stay as they were
    assert set(scan.DRUM_FIELDS) == set(scan.DRUM_DEFAULTS)


def test_drum_cases_vary_one_field_at_a_time_or_on_a_grid():
    cases = scan.one_at_a_time(dict(DRUM, viscosity=5.0), viscosity=[5, 50], rpm=[30])
    assert [(c['viscosity'], c['rpm']) for c in cases] == [(5.0, 0.0), (50.0, 0.0), (5.0, 30.0)]
    assert all(c['kind'] == 'drum' for c in cases)
    assert len(scan.grid(DRUM, viscosity=[5, 50], wetFraction=[0.1, 0.2])) == 4
    with pytest.raises(ValueError, match='kind cannot be varied'):
        scan.one_at_a_time({}, kind=['settling', 'drum'])
    with pytest.raises(ValueError, match=r'unknown field\(s\) steps of a drum case'):
        scan.grid(DRUM, steps=[10])


@pytest.mark.parametrize('field, value', [
    ('n', 0), ('radius', 0.0), ('drumRadius', -1.0), ('froude', 0.0), ('froude', 1.5), ('rpm', -1.0),
    ('viscosity', -1.0), ('wetFraction', 1.5), ('filmRel', -0.1), ('minBridgeRel', 2.0), ('revolutions', 0.0),
    ('liquidModel', 'spray'), ('integration', 'semi'), ('segments', 4), ('wallFriction', 2.0), ('seed', 1.5)])
def test_drum_values_out_of_range_are_rejected_naming_the_field(field, value):
    with pytest.raises(ValueError, match=r'scan case: %s=.* is out of range; allowed: ' % field):
        scan.normalize_case(dict(DRUM, **{field: value}))


def test_drum_fields_are_checked_together_before_anything_runs():
    with pytest.raises(ValueError, match='froude=0.1 and rpm=30.0 both set the drum speed'):
        scan.normalize_case(dict(DRUM, froude=0.1, rpm=30))
    with pytest.raises(ValueError, match='drumRadius=0.004 and length=0.01 .* at least 5 and 4 sphere radii'):
        scan.normalize_case(dict(DRUM, drumRadius=0.004))
    with pytest.raises(ValueError, match="kind='box' is not a known kind; allowed: 'settling', 'drum'"):
        scan.normalize_case(dict(kind='box'))


def test_a_drum_case_gives_the_drum_its_parameters_and_one_speed():
    args = scan.drum_arguments(dict(DRUM, viscosity=50, n=60))
    assert args['viscosity'] == 50.0 and args['n'] == 60 and args['froude'] == 0.05
    assert 'rpm' not in args and 'revolutions' not in args and 'kind' not in args
    by_rpm = scan.drum_arguments(dict(DRUM, rpm=30))
    assert by_rpm['rpm'] == 30.0 and 'froude' not in by_rpm
    with pytest.raises(ValueError, match="drum_arguments: the case's kind='settling' is out of range"):
        scan.drum_arguments({})


def test_a_drum_case_sprays_binder_by_its_spray_fields():
    """sprayRel (the binder over the particles' volume), sprayRevolutions and sprayStart describe
    Drum.spray, not scenes.drum; at their defaults (no spray) they leave the key as it was, so drum
    scans run before them resume."""
    before = scan.case_key(dict(DRUM, viscosity=5.0))
    assert scan.case_key(dict(DRUM, viscosity=5.0, sprayRel=0.0, sprayRevolutions=1.0, sprayStart=0.0, sprayDropletRel=0.0)) == before
    assert scan.case_key(dict(DRUM, viscosity=5.0, sprayRel=0.02)) != before
    args = scan.drum_arguments(dict(DRUM, sprayRel=0.02, sprayRevolutions=2))
    assert not set(args) & {'sprayRel', 'sprayRevolutions', 'sprayStart', 'sprayDropletRel'}
    with pytest.raises(ValueError, match=r"sprayRel=0.02 needs liquidModel='film'"):
        scan.normalize_case(dict(DRUM, sprayRel=0.02, liquidModel='fixed'))
    for field, value in (('sprayRel', 1.5), ('sprayRel', -0.1), ('sprayRevolutions', 0.0), ('sprayStart', -1.0),
                         ('sprayDropletRel', -0.5)):
        with pytest.raises(ValueError, match=r'scan case: %s=.* is out of range' % field):
            scan.normalize_case(dict(DRUM, **{field: value}))


def test_a_table_holds_cases_of_one_kind_with_their_columns(tmp_path):
    settling = open(scan.write_table([{}], str(tmp_path / 'settling.table'), str(tmp_path))).read().splitlines()
    assert settling[0].split() == ['description'] + list(scan.CASE_DEFAULTS) + ['scanDir']  # as before drums
    drum = open(scan.write_table(scan.one_at_a_time(dict(DRUM, viscosity=5.0), viscosity=[50]),
                                 str(tmp_path / 'drum.table'), str(tmp_path))).read().splitlines()
    assert drum[0].split() == ['description', 'kind'] + list(scan.DRUM_DEFAULTS) + ['scanDir'] and len(drum) == 3
    assert drum[1].split()[1] == "'drum'"
    with pytest.raises(ValueError, match='cases of one kind; got drum and settling'):
        scan.write_table([{}, DRUM], str(tmp_path / 'mixed.table'), str(tmp_path))
    assert not (tmp_path / 'mixed.table').exists()


def test_the_command_line_takes_a_kind_and_lists_its_fields(tmp_path, capsys):
    assert scan.main(['table', str(tmp_path), '--kind', 'drum', '--base', 'n=40', '--vary', 'viscosity=5,50']) == 0
    lines = (tmp_path / 'cases.table').read_text().splitlines()
    assert len(lines) == 1 + 3 and all(" 'drum' 40 " in line for line in lines[1:])
    assert scan.main(['table', str(tmp_path / 'x'), '--kind', 'drum', '--base', 'kind=settling']) == 1
    assert '--kind drum and --base kind=settling disagree' in capsys.readouterr().err
    help_text = scan.fields_help()
    assert 'drum case fields (--kind drum' in help_text and 'revolutions' in help_text and 'steps' in help_text
