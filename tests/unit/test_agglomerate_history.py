"""AgglomerateHistory without YADE: the granule statistics of one set of agglomerates, the CSV's header
and the sidecar of the run's parameters, argument checks, and the plot of rows recorded so far.
(On scenes: tests/yade/test_agglomerates_scene.py and test_drum.py.)"""
import json
import math

import pytest
from PIL import Image

from viscbridge.analysis.agglomerate_history import (COLUMN_INFO, COLUMNS, AgglomerateHistory, sidecar_path,
                                                      statistics)
from viscbridge.analysis.agglomerates import components
from history_rows import record


def test_granules_leave_single_spheres_out_and_agglomerates_count_them():
    """Ten spheres: a chain of 3, a pair and 5 lone spheres.  Half of the mass is granulated, so the
    mass median of all agglomerates is still a lone sphere, while that of the granules is the chain."""
    a = components(list(range(10)), [(0, 1), (1, 2), (3, 4)], [1.0] * 10)
    s = statistics(a)
    assert (s['spheres'], s['agglomerates'], s['granules'], s['largest']) == (10, 7, 2, 3)
    assert s['granulated_mass_fraction'] == pytest.approx(0.5)
    assert s['d50'] == 1 and s['granule_d50'] == 3 and s['granule_mean_size'] == pytest.approx(2.5)
    assert s['bridges'] == 3 and s['coordination'] == pytest.approx(0.6)


def test_the_granule_d50_weighs_granules_by_mass():
    """Three light pairs and one heavy chain of 3: by number most granules are pairs, by mass most of
    the granulated mass is in the chain."""
    masses = [1.0] * 6 + [10.0] * 3
    a = components(list(range(9)), [(0, 1), (2, 3), (4, 5), (6, 7), (7, 8)], masses)
    s = statistics(a)
    assert s['granules'] == 4 and s['granule_d50'] == 3 and s['granule_mean_size'] == pytest.approx(9 / 4)
    assert s['granulated_mass_fraction'] == pytest.approx(1.0)


def test_without_bridges_there_is_no_granule():
    s = statistics(components([1, 2, 3], [], [1.0, 1.0, 1.0]))
    assert (s['agglomerates'], s['granules'], s['largest'], s['d50']) == (3, 0, 1, 1)
    assert s['granulated_mass_fraction'] == 0.0
    assert math.isnan(s['granule_d50']) and math.isnan(s['granule_mean_size'])
    empty = statistics(components([], [], []))
    assert (empty['spheres'], empty['agglomerates'], empty['granules']) == (0, 0, 0)
    assert math.isnan(empty['granulated_mass_fraction'])


def test_every_column_is_described_once():
    a = components([0, 1], [(0, 1)], [1.0, 1.0], liquid=[1.0, 1.0])
    measured = set(statistics(a)) | {'t', 'iter', 'revolutions', 'liquid_sprayed', 'broken', 'merged'}
    assert set(COLUMNS) == measured and list(COLUMN_INFO) == list(COLUMNS)
    assert COLUMN_INFO['t'].unit == 's' and COLUMN_INFO['liquid_sprayed'].unit == 'm³'
    assert all(c.meaning and c.label for c in COLUMN_INFO.values())


def test_the_header_and_the_sidecar_are_written_when_the_history_is_made(tmp_path):
    path = tmp_path / 'run' / 'agglomerates.csv'
    h = AgglomerateHistory(str(path), period=2.0, params=dict(viscosity=5, label='wet', sprayed=None),
                           units=dict(label=''))
    assert path.read_text() == ','.join(COLUMNS) + '\n'
    side = json.loads((tmp_path / 'run' / 'agglomerates.json').read_text())
    assert sidecar_path(str(path)) == str(tmp_path / 'run' / 'agglomerates.json')
    assert side['period'] == 2.0 and side['csv'] == 'agglomerates.csv'
    assert side['params'] == dict(viscosity=5, label='wet', sprayed=None)
    assert side['units']['viscosity'] == 'Pa·s'  # an Ip2 parameter's unit, from the C++ table
    assert side['columns']['granule_d50'] == dict(unit='spheres', meaning=COLUMN_INFO['granule_d50'].meaning)
    assert h.rows == [] and h.period == 2.0


@pytest.mark.parametrize('kw, name', [
    (dict(period=0.0), 'period'), (dict(period=float('nan')), 'period'), (dict(params=[1]), 'params'),
    (dict(params=dict(viscosity=float('inf'))), 'params'), (dict(params={1: 2}), 'params'),
    (dict(params=dict(x=[1, 2])), 'params'), (dict(units=dict(viscosity=1)), 'units'), (dict(drum=object()), 'drum'),
    (dict(min_force=-1.0), 'min_force'),
])
def test_bad_arguments_name_themselves(tmp_path, kw, name):
    with pytest.raises(ValueError, match=r'AgglomerateHistory: %s=.* is out of range; allowed: ' % name):
        AgglomerateHistory(str(tmp_path / 'a.csv'), **kw)
    assert not (tmp_path / 'a.csv').exists()


def test_a_drum_and_a_period_are_one_too_many(tmp_path):
    with pytest.raises(ValueError, match='drum=... or period=...'):
        AgglomerateHistory(str(tmp_path / 'a.csv'), drum=object(), period=1.0)
    with pytest.raises(ValueError, match='csv_path'):
        AgglomerateHistory(str(tmp_path / 'a.json'))


def test_the_plot_shows_the_rows_recorded_so_far_against_revolutions(tmp_path):
    h = AgglomerateHistory(str(tmp_path / 'agglomerates.csv'), period=0.5)
    for k, edges in enumerate([[], [(0, 1)], [(0, 1), (1, 2)], [(0, 1), (1, 2), (3, 4)]]):
        record(h, 0.1 * k, edges)
    png = h.plot(str(tmp_path / 'agglomerates.png'))
    assert open(png, 'rb').read(8) == b'\x89PNG\r\n\x1a\n'
    description = Image.open(png).text['Description']  # what the PNG says it shows
    assert description.startswith('4 rows of ') and '(0.6 revolutions)' in description
    record(h, 0.4, [(0, 1)])
    assert Image.open(h.plot(png, x='t')).text['Description'].startswith('5 rows of ')
    with pytest.raises(ValueError, match="x='time'"):
        h.plot(png, x='time')


def test_without_a_period_the_plot_is_against_time_and_revolutions_are_refused(tmp_path):
    h = AgglomerateHistory(str(tmp_path / 'agglomerates.csv'))
    with pytest.raises(ValueError, match='nothing recorded yet'):
        h.plot(str(tmp_path / 'a.png'))
    row = record(h, 0.0, [(0, 1)])
    assert math.isnan(row['revolutions'])
    assert h.plot(str(tmp_path / 'a.png'))  # against t
    with pytest.raises(ValueError, match="x='revolutions' needs a period"):
        h.plot(str(tmp_path / 'a.png'), x='revolutions')
    assert (tmp_path / 'agglomerates.csv').read_text().splitlines()[1].split(',')[COLUMNS.index('revolutions')] == 'nan'


def test_the_agglomerates_page_lists_every_column():
    import os
    import re
    doc = open(os.path.join(os.path.dirname(__file__), '..', '..', 'docs', 'agglomerates.md')).read()
    table = doc[doc.index('| column | what it counts |'):doc.index('The sidecar `agglomerates.json`')]
    rows = [line.split('|')[1] for line in table.splitlines()[2:] if line.startswith('|')]
    assert sorted(re.findall(r'`(\w+)`', ' '.join(rows))) == sorted(COLUMNS)  # each column once
