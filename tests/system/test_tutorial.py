"""The tutorials run to the end as a reader runs them: their blocks in order, in one working directory
— the Python blocks in one `yade -n -x` process, each shell block at its place (`./yadew sh CMD` is
CMD here: the tests run inside the environment).  Their numbers are checked where the text states
them."""
import csv
import os
import re

import pytest

from yadeproc import run_yade

DOCS = os.path.join(os.path.dirname(__file__), '..', '..', 'docs')
TUTORIALS = ('tutorial_settling.md', 'tutorial_granulation.md')

SHELL = '''
import subprocess as _subprocess
def _sh(line):
    done = _subprocess.run(['bash', '-c', line], capture_output=True, text=True)
    print(done.stdout)
    if done.returncode:
        raise SystemExit('%s exited with %d:\\n%s' % (line, done.returncode, done.stderr[-3000:]))
'''


def script(name):
    """The tutorial as one script: Python blocks as they are, shell lines as _sh(...) calls."""
    with open(os.path.join(DOCS, name)) as fh:
        blocks = re.findall(r'^```(python|sh)\n(.*?)^```', fh.read(), re.S | re.M)
    parts = [SHELL]
    for language, text in blocks:
        if language == 'python':
            parts.append(text)
        else:
            for line in text.replace('\\\n', ' ').splitlines():
                if line.strip():
                    parts.append('_sh(%r)' % line.replace('./yadew sh ', '', 1))
    return '\n'.join(parts)


@pytest.fixture(scope='module', params=TUTORIALS)
def tutorial(request, tmp_path_factory):
    work = tmp_path_factory.mktemp(request.param.split('.')[0])
    (work / 'tutorial.py').write_text(script(request.param))
    proc, _ = run_yade(str(work / 'tutorial.py'), timeout=1800, cwd=str(work))
    return request.param, work, proc.stdout


def test_every_block_runs_and_writes_what_the_text_says(tutorial):
    name, work, _ = tutorial
    out = work / 'output' / 'tutorial'
    promised = {'tutorial_granulation.md': ['mu1/agglomerates.png', 'mu1/agglomerates.json', 'mu20/agglomerates.csv',
                                            'compare.png', 'compare-cli.png', 'sweep.png', 'sweep/results.csv'],
                'tutorial_settling.md': ['critical/results.csv']}[name]
    for path in promised:
        assert (out / path).exists(), path


def test_the_numbers_are_those_the_text_states(tutorial):
    name, work, out = tutorial
    if name == 'tutorial_settling.md':
        assert 'time stepper:' in out and 'stopped: no' in out.split('time stepper:')[1].splitlines()[0]
        assert re.search(r'Δt = 2.5 t_v = [0-9.e-]+ s: stopped at t = ', out) and 'not stopped' not in out
        ratios = [float(x) for x in re.findall(r'critical Δt [0-9.e-]+ s = ([0-9.]+) t_v', out)]
        assert len(ratios) == 2 and abs(ratios[0] - ratios[1]) < 0.05 * ratios[0] and 1.2 < ratios[0] < 1.4, ratios
        assert re.search(r'implicit at 100 Pa·s: Δt [0-9.e-]+ s \(the collision step\), \d+ steps, stopped: no', out)
        return
    m = re.search(r'sprayed ([0-9.e+-]+) m³ \(([0-9.]+) % of the particles\), delivered ([0-9.e+-]+), pending ([0-9.e+-]+); '
                  r'in the scene ([0-9.e+-]+) m³', out)
    assert m, out
    sprayed, percent, delivered, pending, total = (float(g) for g in m.groups())
    assert percent == pytest.approx(0.3, rel=1e-2) and pending == 0
    assert delivered == pytest.approx(sprayed, rel=1e-3) and total == pytest.approx(delivered, rel=1e-3)
    m = re.search(r'(\d+) of (\d+) spheres carry binder; largest ([0-9.e+-]+) of its sphere, median ([0-9.e+-]+); CoV ([0-9.]+)', out)
    assert m, out
    carry, n, largest, median, cov = int(m.group(1)), int(m.group(2)), float(m.group(3)), float(m.group(4)), float(m.group(5))
    assert 0.4 * n < carry <= n and largest < 0.1 and cov > 0.5
    rows = list(csv.DictReader(open(work / 'output' / 'tutorial' / 'sweep' / 'results.csv')))
    assert sorted(float(r['viscosity']) for r in rows) == [1.0, 20.0]
    assert all(float(r['liquid_sprayed']) > 0 for r in rows)
