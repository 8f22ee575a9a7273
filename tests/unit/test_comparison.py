"""viscbridge.analysis.compare and ``python3 -m viscbridge.analysis compare`` in plain Python (no YADE):
runs read back from their CSV and sidecar, legend labels from the parameters that differ, and clear
errors for missing, empty and foreign files, an unknown x axis and mismatched labels."""
import os
import subprocess
import sys

import pytest

import viscbridge
from viscbridge.analysis import compare
from viscbridge.analysis.agglomerate_history import COLUMNS, AgglomerateHistory
from viscbridge.analysis.comparison import in_order, read_run, run_labels
from history_rows import record

GROWTH = [[], [(0, 1)], [(0, 1), (2, 3)], [(0, 1), (1, 2), (2, 3)]]


def make_run(directory, period=0.5, **params):
    """A run of 6 spheres that granulate over 4 rows, with `params` in its sidecar."""
    h = AgglomerateHistory(str(directory / 'agglomerates.csv'), period=period, params=params or None)
    for k, edges in enumerate(GROWTH):
        record(h, 0.1 * k, edges)
    return str(directory)


@pytest.fixture
def two_runs(tmp_path):
    return [make_run(tmp_path / 'mu5', viscosity=5.0, n=6), make_run(tmp_path / 'mu50', viscosity=50.0, n=6)]


def test_two_runs_are_drawn_and_labelled_by_the_parameter_that_differs(two_runs, tmp_path):
    runs = [read_run(r) for r in two_runs]
    assert run_labels(runs) == ['viscosity = 5 Pa·s', 'viscosity = 50 Pa·s']  # n is the same: left out
    assert list(runs[0].columns['granules']) == [0, 1, 2, 1] and runs[0].period == 0.5
    assert list(runs[1].columns['revolutions']) == pytest.approx([0, 0.2, 0.4, 0.6])
    png = compare(two_runs, str(tmp_path / 'out' / 'cmp.png'))
    assert open(png, 'rb').read(8) == b'\x89PNG\r\n\x1a\n'
    # a CSV path stands for its run as its directory does, and time is an axis too
    assert compare([os.path.join(r, 'agglomerates.csv') for r in two_runs], str(tmp_path / 'cmp.svg'), x='t')


def test_a_sweep_is_drawn_in_the_order_of_its_parameter(tmp_path):
    """Runs given in any order (a shell glob of case-KEY/ directories) come out sorted by the
    parameter that differs, numbers by value (10 after 5, although '10' < '5')."""
    runs = [read_run(make_run(tmp_path / name, viscosity=mu, model=model))
            for name, mu, model in (('c', 10.0, 'x'), ('a', 5.0, 'x'), ('b', 50.0, 'x'))]
    assert [r.name for r in in_order(runs)] == ['a', 'c', 'b']
    assert run_labels(in_order(runs)) == ['viscosity = 5 Pa·s', 'viscosity = 10 Pa·s', 'viscosity = 50 Pa·s']
    mixed = [read_run(make_run(tmp_path / name, viscosity=mu)) for name, mu in (('n', None), ('s', 'high'), ('v', 1.0))]
    assert [r.name for r in in_order(mixed)] == ['v', 's', 'n']


def test_labels_fall_back_to_directory_names(tmp_path):
    same = [read_run(make_run(tmp_path / name, viscosity=5.0)) for name in ('first', 'second')]
    assert run_labels(same) == ['first', 'second']
    bare = make_run(tmp_path / 'bare')
    os.remove(os.path.join(bare, 'agglomerates.json'))  # a run without its sidecar has no parameters
    assert read_run(bare).params == {} and run_labels([read_run(bare), same[0]]) == ['viscosity unset', 'viscosity = 5 Pa·s']
    several = [read_run(make_run(tmp_path / ('s%d' % k), viscosity=5.0, seed=k)) for k in range(2)]
    assert run_labels(several) == ['seed = 0', 'seed = 1']
    assert compare([bare, str(tmp_path / 'first')], str(tmp_path / 'cmp.png'), labels=['dry', 'wet'])


def test_a_last_line_cut_by_a_kill_is_left_out(tmp_path):
    run = make_run(tmp_path / 'cut')
    with open(os.path.join(run, 'agglomerates.csv'), 'a') as fh:
        fh.write('0.4,400,0.8,6')
    assert len(read_run(run).columns['t']) == len(GROWTH)


def write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize('make, says', [
    (lambda d: str(d / 'nowhere'), 'does not exist'),
    (lambda d: (d / 'emptydir').mkdir() or str(d / 'emptydir'), 'is a directory without agglomerates.csv'),
    (lambda d: write(d / 'zero' / 'agglomerates.csv', ''), 'is an empty file'),
    (lambda d: write(d / 'header' / 'agglomerates.csv', ','.join(COLUMNS) + '\n'), 'has no rows yet'),
    (lambda d: write(d / 'settling.csv', 't,Ek,Ep\n0,1,2\n'), 'lacks the column(s) iter, revolutions'),
    (lambda d: write(d / 'old' / 'agglomerates.csv', 't,iter,spheres,agglomerates,largest,largest_mass_fraction,d50,'
                     'mean_size,coordination,liquid_cov,bridges,broken,merged\n0,0,2,2,1,0.5,1,1,0,nan,0,0,0\n'),
     'lacks the column(s) revolutions, granules'),
    (lambda d: write(d / 'text' / 'agglomerates.csv', ','.join(COLUMNS) + '\n' + ','.join(['x'] * len(COLUMNS)) + '\n'),
     'a row that is not a list of numbers'),
    (lambda d: write(d / 'side' / 'agglomerates.csv', open(os.path.join(make_run(d / 'good'), 'agglomerates.csv')).read())
     and write(d / 'side' / 'agglomerates.json', '{"kind": "other"}') and str(d / 'side'), 'not the sidecar'),
])
def test_a_missing_empty_or_foreign_run_is_named(two_runs, tmp_path, make, says):
    bad = make(tmp_path)
    with pytest.raises(ValueError, match=r'compare: runs entry .*') as e:
        compare([two_runs[0], bad], str(tmp_path / 'cmp.png'))
    assert says in str(e.value) and repr(bad) in str(e.value)
    assert not (tmp_path / 'cmp.png').exists()


def test_bad_arguments_name_themselves(two_runs, tmp_path):
    out = str(tmp_path / 'cmp.png')
    with pytest.raises(ValueError, match="compare: x='time' is not a known name; allowed: 'revolutions', 't'"):
        compare(two_runs, out, x='time')
    with pytest.raises(ValueError, match='compare: labels=.* one string per run'):
        compare(two_runs, out, labels=['only one'])
    with pytest.raises(ValueError, match='compare: runs=.* non-empty list'):
        compare([], out)
    with pytest.raises(ValueError, match='compare: runs=.* non-empty list'):
        compare(two_runs[0], out)  # one directory, not a list of them
    with pytest.raises(ValueError, match=r'compare: path=.*\.png, \.pdf or \.svg'):
        compare(two_runs, str(tmp_path / 'cmp.txt'))
    no_period = make_run(tmp_path / 'noperiod', period=None)
    with pytest.raises(ValueError, match="has no revolutions .* allowed for it: x='t'"):
        compare([two_runs[0], no_period], out)
    assert compare([two_runs[0], no_period], out, x='t') == out


def analysis_cli(*args):
    """`python3 -m viscbridge.analysis ARGS` in plain Python: (exit status, stdout, stderr)."""
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(viscbridge.__file__)))
    p = subprocess.run([sys.executable, '-m', 'viscbridge.analysis', *args], capture_output=True, text=True,
                       timeout=120, env=env)
    return p.returncode, p.stdout, p.stderr


def test_the_command_line_writes_the_figure_and_says_where(two_runs, tmp_path):
    out = tmp_path / 'cmp.png'
    status, stdout, stderr = analysis_cli('compare', *two_runs, '-o', str(out), '--title', 'viscosity')
    assert status == 0, stderr
    assert stdout.strip() == str(out) and out.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    status, stdout, _ = analysis_cli('compare', '--help')
    assert status == 0 and '--labels' in stdout and "'revolutions' or 't'" in stdout


@pytest.mark.parametrize('args, says', [
    (['{run}', '{missing}'], 'does not exist'),
    (['{run}', '-x', 'time'], "x='time' is not a known name"),
    (['{run}', '--labels', 'a', 'b'], 'labels='),
])
def test_command_line_errors_are_one_line_and_status_1(two_runs, tmp_path, args, says):
    out = tmp_path / 'cmp.png'
    filled = [a.format(run=two_runs[0], missing=tmp_path / 'missing') for a in args]
    status, stdout, stderr = analysis_cli('compare', *filled, '-o', str(out))
    assert status == 1 and stdout == '' and not out.exists()
    assert len(stderr.strip().splitlines()) == 1 and stderr.startswith('analysis: error: ') and says in stderr, stderr


def test_a_command_line_without_output_is_refused_by_argparse(two_runs):
    status, _, stderr = analysis_cli('compare', *two_runs)
    assert status == 2 and '-o/--output' in stderr
