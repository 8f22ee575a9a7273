"""Every script in examples/ runs as a user runs it (`yade -n -x SCRIPT OUTDIR`, here in its reduced
--quick mode: same code path, fewer particles) and writes what it promises."""
import glob
import os
import re

import pytest

from yadeproc import run_yade

EXAMPLES = os.path.join(os.path.dirname(__file__), '..', '..', 'examples')
# what each example must write into its output directory
PROMISED = {
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
