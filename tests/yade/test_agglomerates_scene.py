"""viscbridge.analysis.agglomerates on scenes: members are the dynamic spheres (a clump counts as one),
edges the liquid bridges between them; walls and fixed bodies join nothing."""
import math

import pytest
from yade import O, utils
import yade.wrapper as yw

import viscbridge
from viscbridge.analysis.agglomerates import agglomerates
from wetpairs import R, material


def chain_on_wall(n=4, gap=0.02):
    """n spheres in a column on a wall, each one `gap`·R above the next, and two lone spheres far
    away on the same wall: bridges within formationDistance."""
    mat = material()
    O.bodies.append(utils.wall(0, axis=2, material=mat))
    column = [O.bodies.append(utils.sphere((0, 0, R * (1 + gap) + k * R * (2 + gap)), R, material=mat)) for k in range(n)]
    lone = [O.bodies.append(utils.sphere((x, 0, R * (1 + gap)), R, material=mat)) for x in (10 * R, 20 * R)]
    O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=1.0, formationDistance=2 * gap * R, timeStepper=False)
    O.dt = 1e-8
    O.run(2, True)
    return column, lone


def test_a_column_on_a_wall_is_one_agglomerate_the_wall_joins_nothing():
    column, lone = chain_on_wall()
    bridges = [(i.id1, i.id2) for i in O.interactions if i.isReal and i.phys.bridge]
    assert len(bridges) == 3 + 1 + 2  # the column's 3, its foot and the two lone spheres on the wall
    a = agglomerates()
    assert list(a.sizes) == [4, 1, 1] and a.largest == 4
    assert {a.label_of(i) for i in column} == {0} and sorted(a.label_of(i) for i in lone) == [1, 2]
    assert a.coordination == pytest.approx(2 * 3 / 6)
    with pytest.raises(KeyError):
        a.label_of(0)  # the wall


def test_a_force_threshold_cuts_bridges_that_carry_nothing():
    chain_on_wall()
    assert list(agglomerates(min_force=1e30).sizes) == [1] * 6


def test_a_saved_scene_gives_the_same_agglomerates(tmp_path):
    chain_on_wall()
    before = agglomerates()
    path = str(tmp_path / 'scene.yade.gz')
    O.save(path)
    O.reset()
    after = agglomerates(path)
    assert list(after.sizes) == list(before.sizes) and list(after.labels) == list(before.labels)


def test_bad_arguments_name_themselves():
    with pytest.raises(ValueError, match='min_force'):
        agglomerates(min_force=-1)
    with pytest.raises(ValueError, match='scene'):
        agglomerates('no/such/file.yade')


def row_of_three(liquidModel='fixed'):
    """Three touching spheres on the x axis moved kinematically (translations blocked: a sphere with
    every degree of freedom blocked is not dynamic for YADE, nor a member), every contact a bridge
    (with 'film' liquid, from films of 1 % of each sphere's volume)."""
    import viscbridge.liquid as liquid
    mat = material()
    ids = [O.bodies.append(utils.sphere((2 * R * k * 0.999, 0, 0), R, material=mat)) for k in range(3)]
    for i in ids:
        O.bodies[i].state.blockedDOFs = 'xyz'
    if liquidModel == 'film':
        liquid.set_film(ids, 0.01 * 4 / 3 * math.pi * R ** 3)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=0.01, timeStepper=False, liquidModel=liquidModel)
    O.dt = 1e-6
    O.run(2, True)
    return ids


def test_a_bridge_that_ruptures_splits_its_agglomerate():
    a, b, c = row_of_three()
    assert list(agglomerates().sizes) == [3]
    O.bodies[c].state.vel = (0.1, 0, 0)  # pulled away until its bridge ruptures
    while any(i.isReal and i.phys.bridge for i in O.interactions if c in (i.id1, i.id2)):
        O.run(100, True)
    split = agglomerates()
    assert list(split.sizes) == [2, 1] and split.label_of(a) == split.label_of(b) == 0 and split.label_of(c) == 1


def test_labels_follow_body_ids_with_gaps_from_erased_bodies():
    mat = material()
    ids = [O.bodies.append(utils.sphere((2 * R * k * 0.999, 0, 0), R, material=mat)) for k in range(6)]
    O.bodies.erase(ids[1])
    O.bodies.erase(ids[4])  # left: 0, then 2-3 touching, then 5 alone
    O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=0.01, timeStepper=False)
    O.dt = 1e-6
    O.run(2, True)
    a = agglomerates()
    assert list(a.ids) == [0, 2, 3, 5] and list(a.sizes) == [2, 1, 1]
    assert a.label_of(2) == a.label_of(3) == 0 and {a.label_of(0), a.label_of(5)} == {1, 2}
    with pytest.raises(KeyError):
        a.label_of(1)


def test_the_history_counts_the_breakage_and_leaves_the_users_names_alone(tmp_path):
    """A recorder's PyRunner runs in the script's namespace: it must not rebind a user's name (it
    once imported itself as `h`)."""
    import __main__
    from viscbridge.analysis.agglomerate_history import AgglomerateHistory
    a, b, c = row_of_three()
    __main__.h = 'the user name'
    history = AgglomerateHistory(str(tmp_path / 'a.csv'))
    O.engines = O.engines + [history.recorder(iterPeriod=100)]
    O.bodies[c].state.vel = (0.1, 0, 0)
    while any(i.isReal and i.phys.bridge for i in O.interactions if c in (i.id1, i.id2)):
        O.run(100, True)
    O.run(100, True)
    assert __main__.h == 'the user name'
    assert sum(r['broken'] for r in history.rows) == 1 and sum(r['merged'] for r in history.rows) == 0
    assert history.rows[-1]['agglomerates'] == 2


def test_the_history_counts_granules_apart_from_single_spheres_and_the_liquid_sprayed(tmp_path):
    """Three bridged spheres, the last pulled off: before, one granule holds all the mass; after, a pair
    holds two thirds and the pulled sphere is a single one — an agglomerate, not a granule.  A spray
    over the spheres meanwhile: each row has the liquid it had put in by then."""
    import viscbridge.liquid as liquid
    from viscbridge.analysis.agglomerate_history import AgglomerateHistory
    a, b, c = row_of_three('film')  # sprays feed films
    before = liquid.sprayed()  # sprays of earlier tests in this process count too
    history = AgglomerateHistory(str(tmp_path / 'a.csv'), period=1e-3)
    O.engines = O.engines + [liquid.spray(rate=1e-9, box=((-R, -R, -R), (5 * R, R, R)), iterPeriod=10)]
    spray = liquid.sprays()[-1]
    whole = history.record()
    assert (whole['agglomerates'], whole['granules'], whole['largest'], whole['granule_d50']) == (1, 1, 3, 3)
    assert whole['granulated_mass_fraction'] == pytest.approx(1.0) and whole['d50'] == 3
    O.bodies[c].state.vel = (0.1, 0, 0)
    while any(i.isReal and i.phys.bridge for i in O.interactions if c in (i.id1, i.id2)):
        O.run(100, True)
    split = history.record()
    assert (split['agglomerates'], split['granules'], split['largest'], split['granule_d50']) == (2, 1, 2, 2)
    assert split['granulated_mass_fraction'] == pytest.approx(2 / 3) and split['broken'] == 1
    assert split['revolutions'] == pytest.approx(O.time / 1e-3)
    assert spray.delivered > 0 and split['liquid_sprayed'] - before == pytest.approx(spray.delivered, rel=1e-12)
    assert 0 <= whole['liquid_sprayed'] - before < spray.delivered


def test_the_state_each_run_ends_in_is_a_row_once(tmp_path):
    """The recorder also writes the row of a run's last step (a run to 350 steps ends between its
    periods), labelled with the step it measures (after the integrator: O.iter + 1); a record() by
    hand of the same state adds nothing, and the recorder's period restarts from a row by hand."""
    from viscbridge.analysis.agglomerate_history import AgglomerateHistory
    row_of_three()
    history = AgglomerateHistory(str(tmp_path / 'a.csv'))
    start = O.iter
    O.engines = O.engines + [history.recorder(iterPeriod=100)]
    O.run(200, True)
    assert history.record() is history.rows[-1]  # the end of that run: a row already
    O.run(150, True)
    assert [r['iter'] - start for r in history.rows] == [0, 100, 200, 300, 350]
    assert history.rows[-1]['t'] == pytest.approx(O.time, rel=1e-12)
    assert len(open(history.csv_path).read().splitlines()) == 1 + 5