"""The product's drum under yade.mpy (docs/cluster.md, "Moving walls and the drum"): its facets, which a
RotationEngine turns and mpy leaves with the master, move on every worker as on the master
(ViscBridgeBoundaryMotion, added by viscbridge.mpi.decompose()), and the run follows the serial one.
tests/system/mpi_drum_case.py is the scene: 150 spheres of 1 mm in a drum of 12 mm at Fr = 0.3,
every contact wet, the implicit scheme; 6 000 steps are 0.093 s, a quarter of a revolution, in
which the bed lands and rolls with ~315 bridges."""
import math
import os

import pytest

from test_mpi import _cache, run_case, run_case_stopping_at_the_first_step

CASE = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'mpi_drum_case.py')
RUN = ('--steps', '6000', '--tolerance', '1e-12')


def centre(result):
    ps = result['positions']
    return [sum(p[a] for p in ps) / len(ps) for a in range(3)]


def test_the_workers_facets_turn_with_the_masters_and_the_bed_follows_the_serial_run():
    """Every facet a worker holds is where the master has it, to the last bit, and where the serial
    run has it; the spheres land within 1e-8 m of the serial run's (measured 1.8e-10 m at the
    solver's tolerance 1e-12; the default 1e-9 leaves 3.4e-5 m between two serial runs as well: the
    bed amplifies any difference), the same bridges form, and the guard's energy checks over the
    ranks (the facets' work booked by the master from the forces mpy sends it) pass."""
    serial = run_case(1, *RUN, case=CASE)[0]
    split = run_case(3, *RUN, case=CASE)
    assert serial['error'] is None and serial['bridges'] > 200
    merged = split[0]
    for r in split:
        assert r['error'] is None and r['iter'] == 6000, r
        assert r['facets'] and all(r['facets'][k] == merged['facets'][k] == serial['facets'][k] for k in r['facets']), r['rank']
    start = run_case(1, '--steps', '1', case=CASE)[0]['facets']
    turned = [math.dist(start[k][:3], serial['facets'][k][:3]) for k in start]
    assert min(turned) > 1e-3  # [m]: every facet's centre moved by more than a sphere's radius
    worst = max(math.dist(p, q) for p, q in zip(serial['positions'], merged['positions']))
    assert worst < 1e-8, worst  # [m]
    assert math.dist(centre(serial), centre(merged)) < 1e-9
    assert merged['bridges'] == serial['bridges'] and merged['guardChecks'] == serial['guardChecks'] > 100


def test_without_boundary_motion_a_turning_drum_is_refused_on_every_rank():
    results = run_case_stopping_at_the_first_step(3, '--no-boundary-motion', case=CASE)
    for r in results:
        assert r['error'] and 'is a boundary that moves (driven by a RotationEngine' in r['error'], r
        assert 'viscbridge.mpi.decompose() adds the engine' in r['error']
        assert r['iter'] <= 1


FILM = ('--n', '300', '--liquid', 'film', '--wet-fraction', '0.5', '--history', '500', '--vtk', '1000', '--steps', '3000',
        '--tolerance', '1e-12')


@pytest.fixture(scope='module')
def film(tmp_path_factory):
    """The film drum serially and on 3 ranks (whose merged scene rank 0 saves): (serial result, every
    rank's result, the saved scene)."""
    saved = str(tmp_path_factory.mktemp('film') / 'merged.yade.gz')
    return run_case(1, *FILM, case=CASE)[0], run_case(3, *FILM, '--save', saved, case=CASE), saved


def test_a_film_drum_on_three_ranks_conserves_its_liquid_and_forms_the_serial_agglomerates(film):
    """Film liquid across ranks (physics.md L8): 300 spheres in a drum of 16 mm, half of them wet,
    3 000 steps (the bed lands and rolls; 276 bridges, 9 of them between the two workers' spheres at
    the end, computed on both).  The liquid over all ranks (a collective measure while the scene is
    split) stays the serial total to 1e-12 at every row, and every worker's copies of its
    neighbours' spheres carry their owners' films; at the end the merged scene's films and bridge
    volumes are the serial run's; the agglomerate history is the serial one row for row (the spheres
    stay within 3e-10 m of the serial run's here — later the mostly dry rolling bed amplifies the
    solver's differences, see docs/cluster.md)."""
    serial, split, _ = film
    assert serial['error'] is None and all(r['error'] is None for r in split), [r['error'] for r in split]
    total = serial['initialLiquid']
    assert total > 0 and abs(serial['finalLiquid'] - total) <= 1e-12 * total
    rows = [row for r in split for row in r['liquid']]
    assert len(rows) == 3 * len(serial['liquid']) >= 3 * 5
    assert all(abs(row[1] - total) <= 1e-12 * total for row in rows), rows  # every rank, every row
    measured = [[row[:5] for row in r['liquid']] for r in split]  # iter, total, films, CoV, spheres
    assert measured[0] == measured[1] == measured[2]  # every rank measured the whole scene
    assert [row[3:5] for row in measured[0]] == [row[3:5] for row in serial['liquid']]
    across = [row[5] for row in split[1]['liquid']]  # bridges between the two workers' spheres, held by both
    assert across == [row[5] for row in split[2]['liquid']] and across[-1] >= 5, across
    assert all(row[6] == 0 for row in rows)  # every mirror's film is its owner's (the law reads them)
    merged = split[0]
    assert abs(merged['finalLiquid'] - total) <= 1e-12 * total
    assert max(abs(a - b) for a, b in zip(serial['films'], merged['films'])) <= 1e-12 * total
    assert [b[:2] for b in merged['bridgeVolumes']] == [b[:2] for b in serial['bridgeVolumes']]
    assert max(abs(a[2] - b[2]) for a, b in zip(serial['bridgeVolumes'], merged['bridgeVolumes'])) <= 1e-12 * total
    assert merged['history'] == serial['history'] and serial['history'][-1]['bridges'] > 200
    assert max(math.dist(p, q) for p, q in zip(serial['positions'], merged['positions'])) < 1e-8  # [m]


def by_id(frame, kind, key, names):
    """The rows of a VTK frame's arrays `names`, by the value of array `key` (pieces joined)."""
    arrays = frame[kind]['arrays']
    return dict(zip(arrays[key], zip(*(arrays[n] for n in names))))


def test_the_film_drums_vtk_series_on_three_ranks_holds_the_serial_frames_in_pieces(film):
    """The film drum with a viscbridge.vtk.bridge_recorder every 1 000 steps: on 3 ranks each frame
    of the split scene is one piece per rank (listed as the frame's parts in the .pvd, which rank 0
    writes), and the pieces of the last frame hold every sphere, interaction and facet once, with
    the serial frame's values (films, agglomerate labels and bridge volumes equal; positions
    within 1e-8 m; the liquid per sphere, whose bridge shares a rank sums in its own order, to 1e-14)."""
    serial, split = film[0]['vtk'], film[1][0]['vtk']
    for kind in ('bridges', 'particles', 'boundary'):
        assert serial[kind]['pieces'] == ['0'] and split[kind]['pieces'] == ['0', '1', '2'], kind
        assert serial[kind]['frames'] == split[kind]['frames'] == 4, kind  # steps 0 (whole, rank 0), 1000, 2000, 3000
    names = ('film', 'liquid', 'agglomerate', 'radius')
    spheres, pieces = by_id(serial, 'particles', 'id', names), by_id(split, 'particles', 'id', names)
    assert len(split['particles']['arrays']['id']) == len(pieces) == len(spheres) == 300
    assert pieces.keys() == spheres.keys()
    for i, (film, liquid, label, radius) in spheres.items():  # a sphere's bridges summed in the rank's order: liquid to rounding
        assert pieces[i][0] == film and pieces[i][2:] == (label, radius) and math.isclose(pieces[i][1], liquid, rel_tol=1e-14), i
    pairs = [sorted(zip(f['bridges']['arrays']['id1'], f['bridges']['arrays']['id2'], f['bridges']['arrays']['bridgeVolume']))
             for f in (serial, split)]
    assert pairs[0] == pairs[1] and sum(1 for p in pairs[0] if p[2] > 0) > 200  # each interaction once, its bridge's liquid
    points = [f['particles']['arrays']['Points'] for f in (serial, split)]
    order = [f['particles']['arrays']['id'] for f in (serial, split)]
    at = [{i: p[3 * k:3 * k + 3] for k, i in enumerate(ids)} for ids, p in zip(order, points)]
    assert max(math.dist(at[0][i], at[1][i]) for i in at[0]) < 1e-8
    assert sorted(serial['boundary']['arrays']['id']) == sorted(split['boundary']['arrays']['id'])
    assert serial['boundary']['arrays']['Points'] == split['boundary']['arrays']['Points']  # the master's facets


def test_the_film_drum_merged_saved_and_run_on_serially_keeps_its_liquid(film):
    """The 3-rank film drum's merged scene, saved by rank 0, loaded in one process, made serial
    (viscbridge.mpi.to_serial()) and run 3 000 steps more: its liquid is the total put in to 1e-12
    before and after, while bridges go on forming from the films."""
    serial, split, saved = film
    assert split[0]['error'] is None and os.path.exists(saved)
    resumed = run_case(1, '--load', saved, '--steps', '3000', case=CASE)[0]
    total = serial['initialLiquid']
    assert resumed['iter'] == 6000 and resumed['formed'] > 10, resumed
    assert all(abs(v - total) <= 1e-12 * total for v in resumed['liquid']), (resumed['liquid'], total)


def test_a_film_drum_on_three_workers_is_the_serial_one_as_well(film):
    """The same film drum on 4 ranks (3 workers; this 2-core machine oversubscribed): the middle
    worker exchanges films with two neighbours.  Liquid to 1e-12 at every row on every rank, no
    stale mirror film, films, bridges and the agglomerate history the serial run's."""
    serial = film[0]
    split = run_case(4, *FILM, case=CASE)
    assert all(r['error'] is None for r in split), [r['error'] for r in split]
    total = serial['initialLiquid']
    rows = [row for r in split for row in r['liquid']]
    assert all(abs(row[1] - total) <= 1e-12 * total and row[6] == 0 for row in rows), rows
    assert all(r['liquid'][-1][5] > 0 for r in split[1:])  # every worker holds bridges to a neighbour's spheres
    merged = split[0]
    assert merged['films'] == serial['films'] and merged['bridgeVolumes'] == serial['bridgeVolumes']
    assert merged['history'] == serial['history']


def test_bodies_moved_between_ranks_are_refused_with_film_liquid():
    """mpy.migrateBodies (what mpy's reallocation does) between two runs of a film drum: a moved body's
    bridges would be created anew on its new rank and take their liquid again, so the first step
    after it stops on every rank, naming REALLOCATE_FREQUENCY — twice in a row, none hanging."""
    for attempt in range(2):
        _cache.clear()
        results = run_case(3, '--liquid', 'film', '--wet-fraction', '0.5', '--steps', '60', '--migrate', '50', case=CASE)
        for r in results:
            assert r['error'] and 'yade.mpy moved bodies between ranks' in r['error'], (attempt, r)
            assert 'mp.REALLOCATE_FREQUENCY = 0' in r['error'] and r['iter'] == 50
