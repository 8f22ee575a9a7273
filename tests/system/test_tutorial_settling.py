"""docs/tutorial_settling.md runs to the end (tutorial_runner.py), and prints what its text states."""
import re

from tutorial_runner import tutorial_fixture

run = tutorial_fixture('tutorial_settling.md')


def test_every_block_runs_and_writes_its_files(run):
    work, _ = run
    assert (work / 'output' / 'tutorial' / 'critical' / 'results.csv').exists()


def test_the_numbers_are_those_the_text_states(run):
    _, out = run
    assert 'time stepper:' in out and 'stopped: no' in out.split('time stepper:')[1].splitlines()[0]
    assert re.search(r'Δt = 2.5 t_v = [0-9.e-]+ s: stopped at t = ', out) and 'not stopped' not in out
    ratios = [float(x) for x in re.findall(r'critical Δt [0-9.e-]+ s = ([0-9.]+) t_v', out)]
    assert len(ratios) == 2 and abs(ratios[0] - ratios[1]) < 0.05 * ratios[0] and 1.2 < ratios[0] < 1.4, ratios
    assert re.search(r'implicit at 100 Pa·s: Δt [0-9.e-]+ s \(the collision step\), \d+ steps, stopped: no', out)
