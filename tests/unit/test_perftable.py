"""docs/_ext/perftable.py: the manual's measured numbers come from docs/perf/*.csv.

The CSV functions (selection, derived columns, formatting, errors that name what is missing) are
tested on a small CSV of their own; then every ``{perf}`` role and ``perf-table`` directive of
docs/*.md must resolve against the CSVs in the tree, so that a re-run of a bench that renames a
column or drops a row fails here, not in front of a reader."""
import glob
import os
import sys

import pytest

TOP = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
sys.path.insert(0, os.path.join(TOP, 'docs', '_ext'))
import perftable  # noqa: E402

CSV = """viscosity,run,dt,steps,wall_seconds,ratio,note
1.0,implicit,8.65e-06,11556,7.06,1.28,
1.0,explicit,1.02e-07,984406,118.8,,projected
100.0,implicit,8.65e-06,11556,8.02,1.50,
100.0,explicit,1.02e-09,98440600,11880.0,,projected
"""


@pytest.fixture
def docs(tmp_path):
    (tmp_path / 'perf').mkdir()
    (tmp_path / 'perf' / 'runs.csv').write_text(CSV)
    return str(tmp_path)


def test_load_keeps_rows_in_order_as_text(docs):
    rows = perftable.load('perf/runs.csv', docs)
    assert [r['run'] for r in rows] == ['implicit', 'explicit'] * 2
    assert rows[0]['dt'] == '8.65e-06' and rows.columns[0] == 'viscosity'


def test_a_bare_file_name_is_looked_up_in_perf(docs):
    assert perftable.load('runs.csv', docs) == perftable.load('perf/runs.csv', docs)


def test_select_compares_numbers_as_numbers_and_text_as_text(docs):
    rows = perftable.load('runs.csv', docs)
    assert len(perftable.select(rows, 'viscosity=100')) == 2  # 100 matches 100.0
    assert [r['viscosity'] for r in perftable.select(rows, 'run=implicit')] == ['1.0', '100.0']
    assert len(perftable.select(rows, 'viscosity>1,run!=explicit')) == 1
    assert len(perftable.select(rows, 'viscosity=1;100,run=explicit')) == 2  # either value
    assert len(perftable.select(rows, 'note=')) == 2  # empty cells
    assert len(perftable.select(rows, '')) == 4


def test_value_formats_and_derives(docs):
    v = perftable.value
    assert v('runs.csv', 'viscosity=100,run=implicit', 'ratio', '%.2f', docs) == '1.50'
    assert v('runs.csv', 'viscosity=100,run=implicit', 'wall_seconds', '%.1f s', docs) == '8.0 s'
    assert v('runs.csv', 'viscosity=100,run=explicit', 'steps', 'int', docs) == '98\u202f440\u202f600'
    assert v('runs.csv', 'viscosity=1,run=explicit', 'dt', 'sci3', docs) == '1.02·10⁻⁷'
    assert v('runs.csv', 'viscosity=1,run=explicit', 'dt', '%.2e', docs) == '1.02·10⁻⁷'
    assert v('runs.csv', 'viscosity=1,run=explicit', 'dt', 'sci', docs) == '1.02·10⁻⁷'
    assert v('runs.csv', 'viscosity=100,run=explicit', 'wall_seconds / 3600', '%.1f h', docs) == '3.3 h'
    assert v('runs.csv', 'viscosity=1,run=implicit', 'steps', '%d', docs) == '11556'
    assert v('runs.csv', 'viscosity=100,run=explicit', 'steps / 23.07', 'sig3', docs) == '4\u202f270\u202f000'
    assert v('runs.csv', 'viscosity=1,run=implicit', 'steps / 2078.4', 'sig3', docs) == '5.56'
    assert v('runs.csv', 'viscosity=1,run=implicit', 'run', None, docs) == 'implicit'
    assert v('runs.csv', 'viscosity=1,run=implicit', 'ratio', None, docs) == '1.28'  # %.3g by default
    assert v('runs.csv', 'viscosity=1,run=explicit', 'ratio', '%.2f', docs) == '–'  # empty cell
    assert v('runs.csv', 'viscosity=1,run=explicit', 'ratio * 2', '%.2f', docs) == '–'  # empty in an expression
    assert v('runs.csv', 'viscosity=1,run=explicit', 'note', 'map:projected=*;=', docs) == '*'
    assert v('runs.csv', 'viscosity=1,run=explicit', 'dt * 1e7 / 1.02', 'sci1', docs) == '1'
    assert v('runs.csv', 'viscosity=1,run=explicit', 'dt / 1.02', 'sci1', docs) == '10⁻⁷'
    with pytest.raises(perftable.PerfError, match='not one of the values'):
        v('runs.csv', 'viscosity=1,run=implicit', 'run', 'map:explicit=E', docs)


def test_table_renders_the_selected_rows(docs):
    headers, body = perftable.table('runs.csv', 'viscosity | μ [Pa·s] | %g\nsteps | | int\n# a comment\nmax(wall_seconds, 10) | at least 10 s | %.0f',
                                    'run=implicit', docs)
    assert headers == ['μ [Pa·s]', 'steps', 'at least 10 s']
    assert body == [['1', '11\u202f556', '10'], ['100', '11\u202f556', '10']]


@pytest.mark.parametrize('path, where, column, named', [
    ('missing.csv', '', 'ratio', 'missing.csv'),                            # no such file
    ('runs.csv', 'mu=100', 'ratio', "'mu'"),                                # no such column in WHERE
    ('runs.csv', 'viscosity=100,run=implicit', 'ratio_to_yade', "'ratio_to_yade'"),  # no such column
    ('runs.csv', 'viscosity=100,run=implicit', 'wall / steps', "'wall'"),    # ... in an expression
    ('runs.csv', 'viscosity=10,run=implicit', 'ratio', "'viscosity=10,run=implicit' selects 0 rows"),
    ('runs.csv', 'viscosity=100', 'ratio', "selects 2 rows"),               # not one row
    ('runs.csv', 'viscosity~100', 'ratio', "'viscosity~100'"),              # not a condition
])
def test_errors_name_what_is_missing(docs, path, where, column, named):
    with pytest.raises(perftable.PerfError) as e:
        perftable.value(path, where, column, None, docs)
    assert named in str(e.value)


def test_errors_in_formats_and_expressions(docs):
    with pytest.raises(perftable.PerfError, match='not a number'):
        perftable.value('runs.csv', 'viscosity=1,run=implicit', 'run', '%.2f', docs)
    with pytest.raises(perftable.PerfError, match='only column names'):
        perftable.value('runs.csv', 'viscosity=1,run=implicit', '__import__("os")', None, docs)
    with pytest.raises(perftable.PerfError, match='printf'):
        perftable.value('runs.csv', 'viscosity=1,run=implicit', 'ratio', '.2f', docs)
    with pytest.raises(perftable.PerfError, match='FILE|WHERE'):
        perftable.parse_role('runs.csv|ratio')


def test_references_are_found_in_markdown_outside_other_code_blocks():
    text = '\n'.join([
        'The ratio is {perf}`runs.csv|viscosity=100,run=implicit|ratio|%.2f` today.',
        '```sh',
        'echo {perf}`not.csv|a=1|b`',
        '```',
        '````{perf-table} perf/runs.csv',
        ':where: run=implicit',
        'viscosity | μ | %g',
        'steps',
        '````',
    ])
    refs = perftable.references(text)
    assert refs[0] == ('value', 1, 'runs.csv|viscosity=100,run=implicit|ratio|%.2f')
    assert refs[1] == ('table', 5, 'perf/runs.csv', {'where': 'run=implicit'}, ['viscosity | μ | %g', 'steps'])
    assert len(refs) == 2


def pages():
    return sorted(glob.glob(os.path.join(TOP, 'docs', '*.md')) + glob.glob(os.path.join(TOP, 'docs', '**', '*.md'), recursive=True))


def test_the_performance_page_takes_its_numbers_from_the_csvs():
    with open(os.path.join(TOP, 'docs', 'performance.md')) as fh:
        kinds = {r[0] for r in perftable.references(fh.read())}
    assert kinds == {'table', 'value'}


@pytest.mark.parametrize('page', sorted(set(pages())), ids=lambda p: os.path.relpath(p, TOP))
def test_every_reference_in_the_docs_points_to_a_row_and_column(page):
    with open(page) as fh:
        refs = perftable.references(fh.read())
    broken = []
    for r in refs:
        try:
            perftable.check_reference(r, os.path.dirname(page))
        except perftable.PerfError as e:
            broken.append('%s:%d: %s' % (os.path.relpath(page, TOP), r[1], e))
    assert not broken, '\n'.join(broken)


def test_ratios_to_a_base_row(docs):
    headers, body = perftable.table('runs.csv', 'viscosity | μ | %g\nbase.wall_seconds / wall_seconds | explicit ÷ implicit | %.0f',
                                    'run=implicit', docs, base='run=explicit', match='viscosity')
    assert body == [['1', '17'], ['100', '1481']]
    assert perftable.value('runs.csv', 'viscosity=100,run=implicit', 'base.steps / steps', '%.0f', docs,
                           base='viscosity=100,run=explicit') == '8519'
    with pytest.raises(perftable.PerfError, match='selects 2 rows for the row'):
        perftable.table('runs.csv', 'base.steps', 'run=implicit', docs, base='run=explicit')  # no match: two rows each
    with pytest.raises(perftable.PerfError, match='no base row'):
        perftable.value('runs.csv', 'viscosity=100,run=implicit', 'base.steps', None, docs)
    assert perftable.parse_role('a.csv|x=1|base.y / y|%.1f|x=2') == ('a.csv', 'x=1', 'base.y / y', '%.1f', 'x=2')
