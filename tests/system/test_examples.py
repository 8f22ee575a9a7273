"""Every script in examples/ runs as a user runs it (`yade -n -x SCRIPT OUTDIR`, here in its reduced
--quick mode: same code path, fewer particles) and writes what it promises."""
import csv
import glob
import os
import re
import signal
import subprocess
import time

import pytest

from yadeproc import run_yade

EXAMPLES = os.path.join(os.path.dirname(__file__), '..', '..', 'examples')
# what each example must write into its output directory
PROMISED = {
    'binder_spray.py': ['binder_spray.csv', 'binder_spray.png'],
    'drum_granulation.py': ['agglomerates.csv', 'agglomerates.json', 'agglomerates.png', 'vtk/drum-bridges.pvd',
                            'vtk/drum-particles.pvd', 'vtk/drum-boundary.pvd'],
    'settling.py': ['settling.png', 'summary.txt'] + ['%s.%s' % (k, x) for k in ('stepper', 'dt_tv', 'dt_2.5tv', 'implicit')
                                                       for x in ('csv', 'png')],
}


def test_every_example_has_its_promise_listed():
    scripts = sorted(os.path.basename(p) for p in glob.glob(os.path.join(EXAMPLES, '*.py')))
    assert scripts == sorted(PROMISED), 'add the new example and the files it writes to PROMISED'


@pytest.mark.parametrize('script', sorted(PROMISED))
def test_example_runs_and_writes_its_files(script, tmp_path):
    out = tmp_path / 'out'
    proc, _ = run_yade(os.path.abspath(os.path.join(EXAMPLES, script)), str(out), '--quick', timeout=900)
    for name in PROMISED[script]:
        path = out / name
        assert path.is_file() and path.stat().st_size > 0, '%s did not write %s' % (script, name)
        if name.endswith('.png'):
            assert path.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    if script == 'settling.py':
        check_settling_story(proc.stdout, (out / 'summary.txt').read_text())
        # the guard's stop is the demonstration working, said once in the summary, not a fatal error
        assert 'FATAL' not in proc.stderr and 'Exception occured' not in proc.stderr and 'ERROR' not in proc.stderr
    if script == 'drum_granulation.py':
        rows = list(csv.DictReader(open(out / 'agglomerates.csv')))
        first, last = rows[0], rows[-1]
        assert int(first['agglomerates']) == 150 and int(first['granules']) == 0  # dropped in as single spheres
        assert int(last['agglomerates']) < 150 and int(last['granules']) > 0  # granules formed
        assert 0 < float(last['granulated_mass_fraction']) < 1 and float(last['revolutions']) == pytest.approx(0.5, abs=1e-3)
    if script == 'binder_spray.py':
        check_spray_story(proc.stdout, (out / 'binder_spray.csv').read_text())


def check_spray_story(stdout, csv):
    """All the binder sprayed is in films and bridges, and bridges formed from it."""
    error = float(re.search(r'relative error of the total ([0-9.e+-]+)', stdout).group(1))
    assert error < 1e-12
    last = csv.splitlines()[-1].split(',')
    assert float(last[1]) > 0 and float(last[3]) > 0 and int(last[5]) > 0


def check_settling_story(stdout, summary):
    """The demonstration: the planning table first, then the stepper and implicit runs stable and the
    2.5 t_v run stopped by the guard with its diagnosis (body, contact, criterion)."""
    assert stdout.index('ViscBridge time-step criteria') < stdout.index('run stepper'), 'the table comes first'
    rows = {line.split('  ')[0].strip(): line for line in summary.splitlines()[1:5]}
    assert 'stable' in rows['explicit, ViscBridgeTimeStepper'] and 'UNSTABLE' not in rows['explicit, ViscBridgeTimeStepper']
    assert 'stable' in rows['implicit, ViscBridgeTimeStepper'] and 'UNSTABLE' not in rows['implicit, ViscBridgeTimeStepper']
    assert 'UNSTABLE' in rows['explicit, fixed dt = 2.5 t_v']
    diagnosis = summary[summary.index('explicit, fixed dt = 2.5 t_v —'):]
    assert 'ViscBridgeGuard stopped the run' in diagnosis
    assert re.search(r'Body #\d+ at', diagnosis) and re.search(r'interaction #\d+\+#\d+', diagnosis)
    assert 'Violated: the explicit viscous pair limit' in diagnosis
    assert 'A safe dt for the current contacts' in diagnosis


def png_rows(path):
    """How many rows of its history a PNG of AgglomerateHistory.plot says it shows."""
    from PIL import Image
    return int(re.match(r'(\d+) rows of ', Image.open(path).text['Description']).group(1))


def test_a_drum_stopped_by_sigterm_keeps_its_csv_and_an_up_to_date_png(tmp_path):
    """The drum example rewrites its PNG after every quarter revolution; SIGTERM (a batch system's
    time limit) half-way through the second quarter stops it with status 143, its CSV holding every
    row recorded and the PNG showing all of them."""
    out = tmp_path / 'out'
    proc = subprocess.Popen(['yade', '-n', '-x', '-j1', os.path.abspath(os.path.join(EXAMPLES, 'drum_granulation.py')),
                             str(out), '--quick'], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=str(tmp_path), env=dict(os.environ, PYTHONUNBUFFERED='1', OMP_NUM_THREADS='1'))
    try:
        for line in proc.stdout:
            if line.startswith('0.25 revolutions'):
                break
        # the plot was brought up to date before that line was printed
        at_quarter = len((out / 'agglomerates.csv').read_text().splitlines()) - 1
        assert 5 <= png_rows(out / 'agglomerates.png') <= at_quarter
        time.sleep(1)  # the second quarter revolution takes about 4 s
        proc.send_signal(signal.SIGTERM)
        stdout, stderr = proc.communicate(timeout=120)
    finally:
        proc.kill()
    assert proc.returncode == 143, stderr[-2000:]
    assert 'interrupted (SIGTERM) at 0.' in stdout
    rows = list(csv.DictReader(open(out / 'agglomerates.csv')))
    assert 0.25 < float(rows[-1]['revolutions']) < 0.5  # stopped mid-run, the stop recorded
    assert len(rows) > at_quarter and png_rows(out / 'agglomerates.png') == len(rows)


@pytest.mark.parametrize('sig, status', [('SIGTERM', 143), ('SIGINT', 130)])
def test_a_stopped_example_keeps_the_run_in_progress(sig, status, tmp_path):
    """Ctrl-C or SIGTERM (a batch system's time limit) during the main example's first run: it stops at
    once and the history of that run so far is saved."""
    out = tmp_path / 'out'
    proc = subprocess.Popen(['yade', '-n', '-x', '-j1', os.path.abspath(os.path.join(EXAMPLES, 'settling.py')), str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=str(tmp_path),
                            env=dict(os.environ, PYTHONUNBUFFERED='1', OMP_NUM_THREADS='1'))
    try:
        for line in proc.stdout:
            if line.startswith('run stepper'):
                break
        time.sleep(3)  # run 1 takes about 40 s
        proc.send_signal(getattr(signal, sig))
        stdout, stderr = proc.communicate(timeout=120)
    finally:
        proc.kill()
    assert proc.returncode == status, stderr[-2000:]
    assert 'interrupted (%s) in run stepper' % ('SIGTERM' if sig == 'SIGTERM' else 'Ctrl-C') in stdout
    history = (out / 'stepper.csv').read_text().splitlines()
    assert len(history) > 3 and (out / 'stepper.png').is_file()
