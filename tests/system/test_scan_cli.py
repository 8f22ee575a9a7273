"""The scan's command line and its runs (``python3 -m viscbridge.scan``, separate processes): errors,
tables, help, the yade-batch route and its results, a failing case, Ctrl-C / SIGTERM stopping
yade-batch with its jobs and resuming, and a scan of drum cases."""
import argparse
import csv
import json
import os
import pathlib
import re
import signal
import subprocess
import sys
import time

import pytest

import viscbridge.scan as scan

TINY = dict(n=40, steps=300, tolerance=0.2, seed=2)


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


# --- drum cases -----------------------------------------------------------------------------------

TINY_DRUM = dict(kind='drum', n=40, drumRadius=0.01, length=0.006, revolutions=0.05, viscosity=5.0)


def test_help_lists_the_drum_fields():
    status, out, err = scan_cli('run', '--help')
    assert status == 0 and '--kind' in out
    for name, default in scan.DRUM_DEFAULTS.items():
        shown = '%g' % default if isinstance(default, float) else str(default)
        unit = scan.DRUM_FIELDS[name].unit or '-'
        assert re.search(r'^  %s +%s +%s +\S' % (name, re.escape(shown), re.escape(unit)), out, re.M), name


def test_a_drum_scan_runs_in_parallel_records_each_case_and_resumes(tmp_path):
    """Two tiny drums (40 spheres, 0.05 revolution) at 5 and 50 Pa·s through yade-batch, 2 at a time:
    each case's result holds its final agglomerate measures, the same as the last row of the
    history it leaves in case-KEY/; run again, nothing runs; the histories compare by viscosity."""
    base = {k: v for k, v in TINY_DRUM.items() if k != 'kind'}
    cli = ['run', str(tmp_path), '--kind', 'drum', '-j', '2', '--base', *assignments(base), '--vary', 'viscosity=5,50']
    status, out, err = scan_cli(*cli)
    assert status == 0, err
    assert 'scan: 2 cases, 0 already done, 2 to run' in err
    rows = {float(r['viscosity']): r for r in csv.DictReader(open(tmp_path / 'results.csv'))}
    assert sorted(rows) == [5.0, 50.0]
    for r in rows.values():
        assert r['kind'] == 'drum' and int(r['spheres']) == 40 and float(r['revolutions']) == 0.05
        granules, agglomerates = int(r['granules']), int(r['agglomerates'])
        assert 0 < granules <= agglomerates < 40  # bridges formed between the 6 wet spheres and their neighbours
        assert 2 <= float(r['granule_d50']) <= int(r['largest']) and 0 < float(r['granulated_mass_fraction']) < 1
        assert float(r['t_end']) == pytest.approx(0.05 * float(r['period']), rel=1e-3)
        history = list(csv.DictReader(open(tmp_path / r['history'])))
        assert len(history) >= 0.05 * 16 + 1 and float(history[-1]['revolutions']) == pytest.approx(0.05, rel=1e-3)
        for column in ('agglomerates', 'granules', 'largest', 'granulated_mass_fraction', 'coordination', 'liquid_cov'):
            assert float(history[-1][column]) == pytest.approx(float(r[column])), column
        assert 'sprayRate' not in r  # not offered until the drum sprays
    status, out, err = scan_cli(*cli)
    assert status == 0 and 'scan: 2 cases, 2 already done, 0 to run' in err, err
    assert len(results_of(tmp_path)) == 2
    from viscbridge.analysis.comparison import read_run, run_labels
    runs = [read_run(str(tmp_path / os.path.dirname(rows[mu]['history']))) for mu in (5.0, 50.0)]
    assert run_labels(runs) == ['viscosity = 5 Pa·s', 'viscosity = 50 Pa·s']
    figure = tmp_path / 'cmp.png'
    p = subprocess.run([sys.executable, '-m', 'viscbridge.analysis', 'compare', *sorted(str(p) for p in tmp_path.glob('case-*/')),
                        '-o', str(figure)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and figure.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n', p.stderr
