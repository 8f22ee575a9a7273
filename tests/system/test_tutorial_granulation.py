"""docs/tutorial_granulation.md runs to the end (tutorial_runner.py), and prints what its text states."""
import csv
import re

import pytest

from tutorial_runner import tutorial_fixture

run = tutorial_fixture('tutorial_granulation.md')


def test_every_block_runs_and_writes_its_files(run):
    work, _ = run
    for path in ('mu1/agglomerates.png', 'mu1/agglomerates.json', 'mu20/agglomerates.csv', 'compare.png', 'compare-cli.png',
                 'sweep.png', 'sweep/results.csv'):
        assert (work / 'output' / 'tutorial' / path).exists(), path


def test_the_binder_is_where_the_text_says(run):
    work, out = run
    m = re.search(r'sprayed ([0-9.e+-]+) m³ \(([0-9.]+) % of the particles\), delivered ([0-9.e+-]+), pending ([0-9.e+-]+); '
                  r'in the scene ([0-9.e+-]+) m³', out)
    assert m, out
    sprayed, percent, delivered, pending, total = (float(g) for g in m.groups())
    assert percent == pytest.approx(0.3, rel=1e-2) and pending == 0
    assert delivered == pytest.approx(sprayed, rel=1e-3) and total == pytest.approx(delivered, rel=1e-3)
    m = re.search(r'(\d+) of (\d+) spheres carry binder; largest ([0-9.e+-]+) of its sphere, median ([0-9.e+-]+); CoV ([0-9.]+)', out)
    assert m, out
    carry, n, largest, cov = int(m.group(1)), int(m.group(2)), float(m.group(3)), float(m.group(5))
    assert 0.4 * n < carry <= n and largest < 0.1 and cov > 0.5
    m = re.search(r'(\d+) granules hold (\d+) % of the mass, granule d50 (\d+) spheres', out)
    assert m and 5 <= int(m.group(1)) <= 30 and 30 <= int(m.group(2)) <= 70, out  # granules, not one lump


def test_the_sweep_has_a_row_per_case(run):
    work, _ = run
    rows = list(csv.DictReader(open(work / 'output' / 'tutorial' / 'sweep' / 'results.csv')))
    assert sorted(float(r['viscosity']) for r in rows) == [1.0, 20.0]
    assert all(float(r['liquid_sprayed']) > 0 for r in rows)
