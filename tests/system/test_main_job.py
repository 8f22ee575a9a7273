"""The README's main job, `./yadew run examples/settling.py`, run in full (not --quick), states what
docs/getting_started.md says it states: the four runs' results, steps, times and last Δt of its
summary table.  (A green suite with a failing main job happened once.)"""
import os
import re

import pytest

from yadeproc import run_yade

TOP = os.path.join(os.path.dirname(__file__), '..', '..')


def documented_rows():
    """The rows of getting_started.md's summary table: run → (last Δt, steps, t, result)."""
    text = open(os.path.join(TOP, 'docs', 'getting_started.md')).read()
    rows = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip('|').split('|')]
        if len(cells) == 5 and cells[0].startswith(('explicit,', 'implicit,')):
            mantissa, exponent = re.match(r'([0-9.]+)(?:·10([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+))?', cells[1]).groups()
            power = int((exponent or '0').translate(str.maketrans('⁻⁰¹²³⁴⁵⁶⁷⁸⁹', '-0123456789')))
            rows[cells[0].replace('Δt', 'dt')] = (float(mantissa) * 10 ** power, int(cells[2].replace(' ', '')), float(cells[3]), cells[4])
    return rows


def test_the_main_job_states_what_getting_started_says(tmp_path):
    documented = documented_rows()
    assert len(documented) == 4
    run_yade(os.path.abspath(os.path.join(TOP, 'examples', 'settling.py')), str(tmp_path / 'out'), timeout=1800)
    for line in (tmp_path / 'out' / 'summary.txt').read_text().splitlines()[1:5]:
        label = re.split(r'\s{2,}', line)[0]
        dt, steps, t = (float(x) for x in line[len(label):].split()[:3])
        doc_dt, doc_steps, doc_t, doc_result = documented[label]
        assert dt == pytest.approx(doc_dt, rel=0.01) and t == pytest.approx(doc_t, rel=0.01), label
        assert steps == doc_steps, label
        assert ('UNSTABLE' in line) == ('unstable' in doc_result) and ('at rest' in doc_result) == ('at rest' in line and 'not yet' not in line), label
