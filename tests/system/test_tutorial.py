"""docs/tutorial_granulation.md runs to the end as a reader runs it: its Python blocks in order in one
`yade -n -x` process, then its shell blocks (`./yadew sh CMD` is CMD here: the tests run inside the
environment), in one working directory.  Its numbers are checked where the text states them."""
import csv
import os
import re
import subprocess

import pytest

from yadeproc import run_yade

TUTORIAL = os.path.join(os.path.dirname(__file__), '..', '..', 'docs', 'tutorial_granulation.md')


def blocks(language):
    with open(TUTORIAL) as fh:
        return re.findall(r'^```%s\n(.*?)^```' % language, fh.read(), re.S | re.M)


def shell_commands():
    """Each shell line, `./yadew sh` dropped (a line ending in a backslash goes on), for bash (globs)."""
    text = '\n'.join(blocks('sh')).replace('\\\n', ' ')
    return [['bash', '-c', line.replace('./yadew sh ', '', 1)] for line in text.splitlines() if line.strip()]


@pytest.fixture(scope='module')
def tutorial(tmp_path_factory):
    work = tmp_path_factory.mktemp('tutorial')
    script = work / 'tutorial.py'
    script.write_text('\n'.join(blocks('python')))
    proc, _ = run_yade(str(script), timeout=1800, cwd=str(work))
    for command in shell_commands():
        done = subprocess.run(command, cwd=str(work), capture_output=True, text=True, timeout=1800)
        assert done.returncode == 0, '%s exited with %d\n%s\n%s' % (command, done.returncode, done.stdout[-3000:], done.stderr[-3000:])
    return work, proc.stdout


def test_every_command_of_the_tutorial_runs(tutorial):
    work, out = tutorial
    for path in ('mu1/agglomerates.png', 'mu1/agglomerates.json', 'mu20/agglomerates.csv', 'compare.png', 'compare-cli.png',
                 'sweep.png', 'sweep/results.csv'):
        assert (work / 'output' / 'tutorial' / path).exists(), path


def test_the_binder_is_where_the_tutorial_says(tutorial):
    _, out = tutorial
    m = re.search(r'sprayed ([0-9.e+-]+) m³ \(([0-9.]+) % of the particles\), delivered ([0-9.e+-]+), pending ([0-9.e+-]+); '
                  r'in the scene ([0-9.e+-]+) m³', out)
    assert m, out
    sprayed, percent, delivered, pending, total = (float(g) for g in m.groups())
    assert percent == pytest.approx(0.3, rel=1e-2) and pending == 0
    assert delivered == pytest.approx(sprayed, rel=1e-3) and total == pytest.approx(delivered, rel=1e-3)
    m = re.search(r'(\d+) of (\d+) spheres carry binder; largest ([0-9.e+-]+) of its sphere, median ([0-9.e+-]+); CoV ([0-9.]+)', out)
    assert m, out
    carry, n, largest, median, cov = int(m.group(1)), int(m.group(2)), float(m.group(3)), float(m.group(4)), float(m.group(5))
    assert 0.4 * n < carry <= n and largest < 0.2 and cov > 0.5


def test_the_sweep_has_a_row_per_case(tutorial):
    work, _ = tutorial
    rows = list(csv.DictReader(open(work / 'output' / 'tutorial' / 'sweep' / 'results.csv')))
    assert sorted(float(r['viscosity']) for r in rows) == [1.0, 20.0]
    assert all(float(r['liquid_sprayed']) > 0 for r in rows)
