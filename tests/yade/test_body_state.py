"""ViscBridgeState: the per-particle quantities ViscBridge's engines own (yade/ViscBridgeState.hpp),
kept in the body's State so that they are saved with the scene, stay with the body when others are
erased or added, and travel with it under yade.mpy."""
import pytest
from yade import O, utils
import yade.wrapper as yw


def test_a_state_converted_keeps_everything_state_had():
    O.bodies.append(utils.sphere((1, 2, 3), 0.5e-3))
    b = O.bodies[0]
    b.state.vel, b.state.angVel, b.state.blockedDOFs = (0.1, 0.2, 0.3), (4, 5, 6), 'xZ'
    before = b.state.dict()
    converted = yw.ViscBridgeState.of(b)
    after = b.state.dict()
    assert isinstance(b.state, yw.ViscBridgeState) and after['film'] == 0
    assert {k: after[k] for k in before} == before
    assert yw.ViscBridgeState.of(b) is not None and b.state.film == converted.film  # a second call converts nothing


def test_a_bad_film_is_refused_and_the_last_value_kept():
    s = yw.ViscBridgeState(film=1e-12)
    with pytest.raises(ValueError, match=r"ViscBridgeState.film=-1 is out of range; allowed: >= 0"):
        s.film = -1
    assert s.film == 1e-12
    with pytest.raises(ValueError, match='film'):
        s.film = float('nan')
    assert s.film == 1e-12


def test_films_survive_erasure_addition_and_save_load(tmp_path):
    ids = O.bodies.append([utils.sphere((3 * i * 1e-3, 0, 0), 0.5e-3) for i in range(4)])
    for i in ids:
        yw.ViscBridgeState.of(O.bodies[i]).film = (i + 1) * 1e-12
    O.bodies.erase(ids[1])
    new = O.bodies.append(utils.sphere((0, 5e-3, 0), 0.5e-3))
    assert not isinstance(O.bodies[new].state, yw.ViscBridgeState)  # a new body starts with a plain State
    path = str(tmp_path / 'films.xml.gz')
    O.save(path)
    O.reset()
    O.load(path)
    assert [O.bodies[i].state.film for i in (ids[0], ids[2], ids[3])] == [1e-12, 3e-12, 4e-12]
    assert O.bodies[ids[1]] is None
