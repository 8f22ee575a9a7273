"""Liquid that is conserved (liquidModel='film', physics.md §11): bridges take their volume from the
particles' films by rule L1–L2 and give it back by L3; the answers below are computed by hand from
those rules."""
import math

import pytest
from yade import O, utils
import yade.wrapper as yw

import viscbridge
import viscbridge.liquid as liquid
from wetpairs import R, material

V = 4.0 / 3.0 * math.pi * R ** 3  # particle volume
CAP = 0.01 * V                    # the Ip2's default bridgeVolumeRel: the largest bridge
PICO = 1e-12


def row(films, gap=0.2 * R, speed=0.05, **effects):
    """Spheres on the x axis, `gap` apart, moved kinematically (blocked degrees of freedom keep their
    velocities): the outer ones approach the middle one at `speed` (or the second one the first,
    for two).  Fixed time step, no stepper: every step is computable."""
    mat = material()
    n = len(films)
    ids = O.bodies.append([utils.sphere(((2 * R + gap) * k, 0, 0), R, material=mat) for k in range(n)])
    for b in O.bodies:
        b.state.blockedDOFs = 'xyzXYZ'
    middle = (n - 1) / 2.0 if n > 2 else 0
    for k, i in enumerate(ids):
        O.bodies[i].state.vel = (-speed * (k - middle) / max(1, abs(k - middle)) if k != middle else 0, 0, 0)
    effects.setdefault('viscosity', 0.01)
    effects.setdefault('liquidModel', 'film')
    O.engines = viscbridge.engines(gravity=(0, 0, 0), timeStepper=False, **effects)
    O.dt = 1e-6
    liquid.set_film(ids, films)
    return ids


def reverse():
    for b in O.bodies:
        b.state.vel = -b.state.vel


def bridges():
    return {(i.id1, i.id2): i.phys.bridgeVolume for i in O.interactions if i.isReal and i.phys.bridge}


def films(ids):
    return [liquid.film(i) for i in ids]


def run_until(condition, limit=20000):
    for _ in range(limit // 10):
        O.run(10, True)
        if condition():
            return
    raise AssertionError('condition not reached in %d steps' % limit)


def test_three_in_a_row_take_by_the_rule_and_give_back_half_each():
    a, b, c = ids = row([1 * PICO, 2 * PICO, 0.5 * PICO])
    before = liquid.total()
    run_until(lambda: len(bridges()) == 2)
    # both bridges form in the same step: b offers half its film to each (L1), a and c all of theirs
    assert bridges() == pytest.approx({(a, b): 2 * PICO, (b, c): 1.5 * PICO}, rel=1e-12)
    assert films(ids) == pytest.approx([0, 0, 0], abs=1e-25)
    assert liquid.total() == pytest.approx(before, rel=1e-12)
    for I in O.interactions:  # the bridge's constants follow its volume (L4): S_rup = V^(1/3) at θ = 0
        assert I.phys.sRup == pytest.approx(I.phys.bridgeVolume ** (1 / 3.0), rel=1e-12)
    reverse()
    run_until(lambda: not bridges())
    # each rupture gives half to each particle (L3)
    assert films(ids) == pytest.approx([1 * PICO, 1.75 * PICO, 0.75 * PICO], rel=1e-12)
    assert liquid.total() == pytest.approx(before, rel=1e-12)
    # the returned liquid forms the next bridges: b offers 1.75/2 to each
    reverse()
    run_until(lambda: len(bridges()) == 2)
    assert bridges() == pytest.approx({(a, b): 1.875 * PICO, (b, c): 1.625 * PICO}, rel=1e-12)
    assert O.engines[[type(e).__name__ for e in O.engines].index('ViscBridgeLiquid')].formed == 4


def test_two_dry_spheres_touch_without_bridge_or_viscous_force():
    row([0, 0])
    run_until(lambda: any(i.isReal and i.geom.penetrationDepth > 0 for i in O.interactions))
    O.run(5, True)
    I = next(i for i in O.interactions if i.isReal)
    assert not I.phys.bridge and I.phys.cn == 0 and I.phys.normalViscousForce.norm() == 0
    assert I.phys.normalContactForce.norm() > 0
    assert liquid.total() == 0


def test_a_wet_and_a_dry_sphere_share_the_wet_ones_film():
    a, b = row([1 * PICO, 0])
    run_until(lambda: bridges())
    assert bridges() == pytest.approx({(a, b): 1 * PICO}, rel=1e-12)
    assert films([a, b]) == [0, 0]


def test_a_bridge_at_its_cap_leaves_the_excess_in_the_films():
    a, b = row([3 * CAP, 1 * CAP])
    run_until(lambda: bridges())
    # capped, each gives in proportion to its offer: 3/4 and 1/4 of the cap
    assert bridges() == pytest.approx({(a, b): CAP}, rel=1e-12)
    assert films([a, b]) == pytest.approx([3 * CAP - 0.75 * CAP, CAP - 0.25 * CAP], rel=1e-12)


def test_no_bridge_forms_from_less_than_the_threshold():
    """L5: films that hold less than minBridgeVolume together leave a dry contact and keep their
    liquid; three in a row whose middle film is shared below the threshold form one bridge, not two."""
    a, b = row([0.4 * PICO, 0.5 * PICO], minBridgeVolume=1 * PICO)
    run_until(lambda: any(i.isReal and i.geom.penetrationDepth > 0 for i in O.interactions))
    O.run(20, True)
    I = next(i for i in O.interactions if i.isReal)
    assert not I.phys.bridge and I.phys.normalViscousForce.norm() == 0
    assert films([a, b]) == pytest.approx([0.4 * PICO, 0.5 * PICO], rel=1e-12)
    O.reset()
    a, b = row([0.6 * PICO, 0.5 * PICO], minBridgeVolume=1 * PICO)
    run_until(lambda: bridges())
    assert bridges() == pytest.approx({(a, b): 1.1 * PICO}, rel=1e-12)
    # two bridges formed in one step share b's film, 0.9 to each: a-b would take 1.0, less than 1.2,
    # and does not form; b-c then takes b's whole film (2.1); a keeps its 0.1, and later a-b has
    # too little (0.1) to form
    O.reset()
    a, b, c = ids = row([0.1 * PICO, 1.8 * PICO, 0.3 * PICO], minBridgeVolume=1.2 * PICO)
    run_until(lambda: bridges())
    assert bridges() == pytest.approx({(b, c): 2.1 * PICO}, rel=1e-12)
    O.run(200, True)
    assert bridges() == pytest.approx({(b, c): 2.1 * PICO}, rel=1e-12)
    assert films(ids) == pytest.approx([0.1 * PICO, 0, 0], abs=1e-25, rel=1e-12)


def test_radius_split_gives_back_by_surface():
    mat = material()
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((3 * R + 0.1 * R, 0, 0), 2 * R, material=mat)])
    for b in O.bodies:
        b.state.blockedDOFs = 'xyzXYZ'
    O.bodies[1].state.vel = (-0.05, 0, 0)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), timeStepper=False, liquidModel='film', viscosity=0.01, ruptureSplit='radius')
    O.dt = 1e-6
    liquid.set_film([0, 1], [PICO, PICO])
    run_until(lambda: bridges())
    reverse()
    run_until(lambda: not bridges())
    assert films([0, 1]) == pytest.approx([0.2 * 2 * PICO, 0.8 * 2 * PICO], rel=1e-12)  # r² : (2r)² = 1 : 4


def sphere_on_wall(film, dry_wall=False):
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, 1.05 * R), R, material=mat)])
    O.bodies[1].state.blockedDOFs = 'xyzXYZ'
    O.bodies[1].state.vel = (0, 0, -0.05)
    if dry_wall:
        liquid.make_dry(material=None, ids=[0])
    O.engines = viscbridge.engines(gravity=(0, 0, 0), timeStepper=False, liquidModel='film', viscosity=0.01)
    O.dt = 1e-6
    liquid.set_film(1, film)


def test_a_wall_bridge_takes_from_the_particle_alone_and_gives_it_all_back():
    sphere_on_wall(1 * PICO)
    run_until(lambda: bridges())
    assert bridges() == pytest.approx({(0, 1): 1 * PICO}, rel=1e-12) and liquid.film(1) == 0
    reverse()
    run_until(lambda: not bridges())
    assert liquid.film(1) == pytest.approx(1 * PICO, rel=1e-12)
    assert not hasattr(O.bodies[0].state, 'film')  # the wall never got a film


def test_a_dry_wall_forms_no_bridge():
    sphere_on_wall(1 * PICO, dry_wall=True)
    run_until(lambda: any(i.isReal and i.geom.penetrationDepth > 0 for i in O.interactions))
    O.run(5, True)
    assert not bridges() and liquid.film(1) == 1 * PICO
    assert next(i for i in O.interactions if i.isReal).phys.normalModel == 'none'


def test_fixed_liquid_ignores_films():
    a, b = row([0, 0], liquidModel='fixed')
    run_until(lambda: bridges())
    assert bridges() == pytest.approx({(a, b): CAP}, rel=1e-12)
    assert not any(isinstance(e, yw.ViscBridgeLiquid) for e in O.engines)


def test_film_without_the_liquid_engine_is_an_error(run_error):
    row([PICO, PICO])
    O.engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeLiquid)]
    message = run_error(20000)
    assert 'ViscBridgeLiquid' in message and "liquidModel='film'" in message


def test_bad_liquid_input_is_refused_by_name():
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, R), R, material=mat)])
    with pytest.raises(ValueError, match='volume'):
        liquid.set_film(1, -1e-12)
    with pytest.raises(ValueError, match='ids'):
        liquid.add(7, 1e-12)
    with pytest.raises(ValueError, match='walls and facets carry no film'):
        liquid.set_film(0, 1e-12)
    with pytest.raises(ValueError, match="liquidModel='nope' is not a known liquid model; allowed: 'fixed', 'film'"):
        yw.Ip2_FrictMat_FrictMat_ViscBridgePhys(liquidModel='nope')
    with pytest.raises(ValueError, match='ruptureSplit'):
        yw.ViscBridgeLiquid(ruptureSplit='thirds')
    with pytest.raises(ValueError, match=r'minBridgeVolume.*>= 0'):
        yw.ViscBridgeLiquid(minBridgeVolume=-1e-12)
    with pytest.raises(ValueError, match="minBridgeVolume.*needs liquidModel='film'"):
        viscbridge.engines(minBridgeVolume=1e-12)
    with pytest.raises(ValueError, match='film'):
        O.bodies[1].state = yw.ViscBridgeState()
        O.bodies[1].state.film = -1


def test_distribution_counts_half_of_each_bridge():
    a, b = row([1 * PICO, 3 * PICO])
    run_until(lambda: bridges())
    d = liquid.distribution()
    assert list(d.ids) == [a, b] and list(d.liquid) == pytest.approx([2 * PICO, 2 * PICO], rel=1e-12)
    assert d.cov == pytest.approx(0, abs=1e-12)


def test_a_saved_film_scene_is_a_film_scene_again_after_loading(tmp_path):
    """The liquid model is not saved with the Ip2 (scenes saved before it existed keep loading): the
    saved ViscBridgeLiquid engine restores it at the first step, and the liquid stays conserved."""
    a, b = row([1 * PICO, 3 * PICO])
    run_until(lambda: bridges())
    path = str(tmp_path / 'film.yade.gz')
    O.save(path)
    O.reset()
    O.load(path)
    O.run(1, True)
    ip2 = next(e for e in O.engines if isinstance(e, yw.InteractionLoop)).physDispatcher.functors[0]
    assert ip2.liquidModel == 'film' and all(i.phys.liquidModel == 'film' for i in O.interactions if i.isReal)
    reverse()
    run_until(lambda: not bridges())
    assert films([a, b]) == pytest.approx([2 * PICO, 2 * PICO], rel=1e-12)


def test_legal_but_implausible_values_are_said_once(capfd):
    capfd.readouterr()
    ip2 = yw.Ip2_FrictMat_FrictMat_ViscBridgePhys()
    ip2.capillaryModel = 'willett'  # surfaceTension still 0
    ip2.viscosity = 1e7
    err = capfd.readouterr().err
    assert "capillaryModel='willett' has no effect while surfaceTension is 0" in err
    assert 'viscosity=1e+07 Pa·s is above 1000 Pa·s' in err
    # bridgeVolume=0.01 meant as 1 %: said at the first bridge, once
    row([0, 0], liquidModel='fixed', bridgeVolume=0.01)
    run_until(lambda: bridges())
    O.run(10, True)
    err = capfd.readouterr().err
    assert err.count('is larger than its particles: bridgeVolume is in m³') == 1
