"""ViscBridgeSpray (viscbridge.liquid.spray): binder onto the spheres the spray reaches (physics.md
L6, L7), conserved, capped, saved with the scene, and loud when its liquid cannot land."""
import math

import pytest
from yade import O, utils
import yade.wrapper as yw

import viscbridge
import viscbridge.liquid as liquid

R = 0.5e-3
VOLUME = 4 / 3 * math.pi * R ** 3


def column_bed(layers=3, side=3, pitch=2 * R):
    """side × side columns of `layers` spheres resting on each other on a floor (film liquid, 10 Pa·s);
    with a pitch above 2 R the columns stand apart.  The floor does not wet."""
    O.bodies.append(utils.wall(0, axis=2))
    liquid.make_dry(ids=[0])
    ids = [O.bodies.append(utils.sphere(((i + 0.5) * pitch, (j + 0.5) * pitch, R + k * 2 * R), R))
           for k in range(layers) for j in range(side) for i in range(side)]
    O.engines = viscbridge.engines(viscosity=10.0, liquidModel='film', integration='implicit')
    O.dt = 1e-6
    return ids


def top_and_below(ids, layers):
    per_layer = len(ids) // layers
    return ids[-per_layer:], ids[:-per_layer]


def test_the_spray_lands_on_the_top_layer_only():
    """Droplets falling straight down wet the first sphere they meet: the top layer of a bed."""
    ids = column_bed()
    top, below = top_and_below(ids, 3)
    O.engines = O.engines + [liquid.spray(rate=1e-9, box=((-R, -R, -R), (7 * R, 7 * R, 9 * R)), iterPeriod=10)]
    O.run(100, True)
    assert all(liquid.film(i) > 0 for i in top)
    assert all(liquid.film(i) == 0 for i in below)
    # the same spheres, equal discs seen from above: equal shares to a few per cent (pixels)
    films = [liquid.film(i) for i in top]
    assert max(films) / min(films) < 1.1


def test_without_a_nozzle_direction_every_sphere_in_the_zone_takes_by_its_cross_section():
    ids = column_bed()
    O.engines = O.engines + [liquid.spray(rate=1e-9, box=((-R, -R, -R), (7 * R, 7 * R, 9 * R)), nozzle=None, iterPeriod=10)]
    O.run(100, True)
    films = [liquid.film(i) for i in ids]
    assert min(films) > 0 and max(films) == pytest.approx(min(films), rel=1e-9)


def test_sprayed_liquid_is_conserved_and_accounted():
    """sprayed = rate × the elapsed window = delivered + pending, and the scene's liquid grows by
    exactly what was delivered."""
    ids = column_bed()
    before = liquid.total()
    spray = liquid.spray(rate=2e-9, box=((-R, -R, -R), (7 * R, 7 * R, 9 * R)), start=1e-4, end=3e-4, iterPeriod=7)
    O.engines = O.engines + [spray]
    while O.time < 5e-4:
        O.run(50, True)
    assert spray.sprayed == pytest.approx(2e-9 * 2e-4, rel=1e-12)
    assert spray.delivered + spray.pending == pytest.approx(spray.sprayed, rel=1e-12)
    assert spray.pending == 0
    assert liquid.total() == pytest.approx(before + spray.delivered, rel=1e-12)
    assert liquid.sprayed() == spray.delivered and liquid.sprays() == [spray]


def test_no_film_grows_beyond_the_cap_and_the_rest_waits(capfd):
    """One sphere under a heavy spray: its film stops at maxFilmRel of its volume, the rest is kept
    pending (not lost, not dumped on it) and YADE's log says so once."""
    ids = column_bed(layers=1, side=1)
    spray = liquid.spray(rate=1e-6, box=((-R, -R, -R), (3 * R, 3 * R, 3 * R)), maxFilmRel=0.05, iterPeriod=10)
    O.engines = O.engines + [spray]
    capfd.readouterr()
    O.run(200, True)
    assert liquid.film(ids[0]) == pytest.approx(0.05 * VOLUME, rel=1e-12)
    assert spray.pending == pytest.approx(spray.sprayed - 0.05 * VOLUME, rel=1e-12)
    err = capfd.readouterr().err
    assert err.count('holds maxFilmRel = 0.05 of its volume') == 1


def test_the_excess_of_a_full_sphere_goes_to_the_others():
    ids = column_bed(layers=1, side=2, pitch=3 * R)  # four spheres apart: no bridge takes from a film
    liquid.set_film(ids[0], 0.1 * VOLUME)  # already full
    spray = liquid.spray(rate=1e-9, box=((-R, -R, -R), (7 * R, 7 * R, 3 * R)), iterPeriod=10)
    O.engines = O.engines + [spray]
    O.run(100, True)
    assert liquid.film(ids[0]) == pytest.approx(0.1 * VOLUME, rel=1e-12)
    assert sum(liquid.film(i) for i in ids[1:]) == pytest.approx(spray.delivered, rel=1e-12)
    assert spray.pending == 0


def test_an_empty_zone_is_not_silent(capfd):
    """Spraying where there is no sphere: the liquid waits, and the log says where and how much."""
    column_bed()
    spray = liquid.spray(rate=1e-9, box=((1, 1, 1), (2, 2, 2)), iterPeriod=10)
    O.engines = O.engines + [spray]
    capfd.readouterr()
    O.run(100, True)
    assert spray.delivered == 0 and spray.pending == pytest.approx(spray.sprayed, rel=1e-12) and spray.pending > 0
    err = capfd.readouterr().err
    assert err.count('is reached by the spray') == 1 and '0 spheres in it' in err


def test_liquid_left_after_the_window_is_said(capfd):
    """Liquid still pending when the spray window ends (the zone emptied) is reported once."""
    column_bed()
    spray = liquid.spray(rate=1e-9, box=((1, 1, 1), (2, 2, 2)), end=5e-5, iterPeriod=10)
    O.engines = O.engines + [spray]
    capfd.readouterr()
    O.run(200, True)
    assert capfd.readouterr().err.count('the spray window ended at t = 5e-05 s') == 1


def test_a_saved_spray_goes_on_where_it_was(tmp_path):
    """Saved with the scene: after O.load the spray continues from the time it had counted up to;
    the run sprays once what the uninterrupted run sprays."""
    column_bed()
    spray = liquid.spray(rate=1e-9, box=((-R, -R, -R), (7 * R, 7 * R, 9 * R)), end=4e-4, iterPeriod=10)
    O.engines = O.engines + [spray]
    O.run(100, True)
    path = str(tmp_path / 'sprayed.xml.bz2')
    O.save(path)
    O.run(300, True)
    straight = (liquid.total(), liquid.sprays()[0].sprayed)
    O.load(path)
    assert liquid.sprays()[0].delivered > 0
    O.run(300, True)
    assert liquid.total() == pytest.approx(straight[0], rel=1e-12)
    assert liquid.sprays()[0].sprayed == pytest.approx(straight[1], rel=1e-12)


@pytest.mark.parametrize('kwargs, parameter', [
    (dict(rate=-1, box=((0, 0, 0), (1, 1, 1))), 'rate'),
    (dict(rate=1e-9), 'zone'),
    (dict(rate=1e-9, box=((0, 0, 0), (1, 1, 1)), ball=((0, 0, 0), 1)), 'zone'),
    (dict(rate=1e-9, box=((1, 0, 0), (0, 1, 1))), 'box'),
    (dict(rate=1e-9, ball=((0, 0), 1)), 'ball'),
    (dict(rate=1e-9, ball=((0, 0, 0), 0)), 'ball radius'),
    (dict(rate=1e-9, box=((0, 0, 0), (1, 1, 1)), start=2, end=1), 'end'),
    (dict(rate=1e-9, box=((0, 0, 0), (1, 1, 1)), nozzle=(0, 0, 0)), 'nozzle'),
    (dict(rate=1e-9, box=((0, 0, 0), (1, 1, 1)), maxFilmRel=0), 'maxFilmRel'),
    (dict(rate=1e-9, box=((0, 0, 0), (1, 1, 1)), iterPeriod=0), 'iterPeriod'),
])
def test_bad_arguments_name_the_parameter(kwargs, parameter):
    with pytest.raises(ValueError, match=parameter):
        liquid.spray(**kwargs)


def test_the_engine_checks_its_own_attributes():
    spray = yw.ViscBridgeSpray()
    with pytest.raises(ValueError, match=r'ViscBridgeSpray.rate=-1 is out of range'):
        spray.rate = -1
    assert spray.rate == 0
    with pytest.raises(ValueError, match='ViscBridgeSpray.maxFilmRel'):
        yw.ViscBridgeSpray(maxFilmRel=0)


def test_an_empty_box_set_by_hand_stops_the_run_with_its_corners(run_error):
    column_bed()
    O.engines = O.engines + [yw.ViscBridgeSpray(rate=1e-9, boxMin=(1, 0, 0), boxMax=(0, 1, 1), iterPeriod=1)]
    assert 'boxMin <= boxMax' in run_error(10)


def test_droplets_land_whole_on_one_sphere_each():
    """L6b: a spray of droplets wets spots: each droplet lands on one reached sphere, whole; the part
    of a droplet sprayed when the window closes lands as a last smaller one.  (Spheres apart: no
    bridge takes from the films.)"""
    top = column_bed(layers=1, side=4, pitch=3 * R)
    drop = 0.01 * VOLUME
    spray = liquid.spray(rate=1e-9, box=((-R, -R, -R), (13 * R, 13 * R, 3 * R)), end=2.05e-4, dropletVolume=drop, iterPeriod=5)
    O.engines = O.engines + [spray]
    while O.time < 3e-4:
        O.run(50, True)
    assert spray.delivered == pytest.approx(spray.sprayed, rel=1e-12) and spray.pending == 0
    assert spray.droplets == math.ceil(spray.sprayed / drop - 1e-9)
    films = sorted(liquid.film(i) for i in top)
    whole = [f / drop for f in films]
    assert sum(1 for w in whole if abs(w - round(w)) > 1e-6) <= 1  # whole droplets, one sphere took the last part
    assert films[0] < films[-1]  # spots, not an even mist


def test_droplet_draws_are_the_same_after_a_save(tmp_path):
    ids = column_bed(layers=1, side=4)
    spray = liquid.spray(rate=1e-7, box=((-R, -R, -R), (9 * R, 9 * R, 3 * R)), dropletVolume=0.005 * VOLUME, seed=3, iterPeriod=5)
    O.engines = O.engines + [spray]
    O.run(100, True)
    path = str(tmp_path / 'drops.xml.bz2')
    O.save(path)
    O.run(200, True)
    straight = [liquid.film(i) for i in ids], liquid.in_bridges(), spray.droplets
    O.load(path)
    O.run(200, True)
    resumed = [liquid.film(i) for i in ids], liquid.in_bridges(), liquid.sprays()[0].droplets
    assert resumed[0] == pytest.approx(straight[0], rel=1e-12, abs=1e-30)
    assert resumed[1:] == pytest.approx(straight[1:], rel=1e-12) and straight[2] > 10


def test_a_spray_starts_now_and_refuses_a_start_already_past():
    """A spray made during a run with a start already past would have delivered the binder of the
    time gone by in its first call (a user's drum got all of it in one step); the default is now."""
    ids = column_bed()
    O.run(200, True)
    with pytest.raises(ValueError, match=r"spray: start=0.0 is out of range; allowed: >= [0-9.e-]+ \[s\], now \(O.time = "):
        liquid.spray(rate=1e-9, box=((-R, -R, -R), (7 * R, 7 * R, 9 * R)), start=0)
    spray = liquid.spray(rate=1e-9, box=((-R, -R, -R), (7 * R, 7 * R, 9 * R)), iterPeriod=10)
    assert spray.start == O.time
    O.engines = O.engines + [spray]
    O.run(100, True)
    assert spray.sprayed == pytest.approx(1e-9 * (O.time - spray.start), rel=0.11)  # since it was made, not since t = 0
    assert liquid.total() == pytest.approx(spray.delivered, rel=1e-12) and len(ids) == 27


def test_a_spray_on_a_scene_without_films_stops_the_run():
    """With liquidModel='fixed' the films feed nothing: a spray there added to a total no bridge used."""
    O.bodies.append(utils.sphere((0, 0, 0), R))
    O.engines = viscbridge.engines(viscosity=10.0) + [liquid.spray(rate=1e-9, ball=((0, 0, 0), 2 * R), iterPeriod=1)]
    O.dt = 1e-6
    with pytest.raises(RuntimeError, match=r"ViscBridgeSpray sprays onto the particles' films, which only .*liquidModel='film'"):
        for _ in range(3):  # O.step() raises in this thread (an exception in the last step of O.run(n, True) can be lost)
            O.step()
    assert liquid.total() == 0
