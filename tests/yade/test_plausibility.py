"""Values no wet granulation run uses — almost always a unit mistake — are said once in YADE's log,
naming the value and the likely slip, and the run goes on (issue: each of these was accepted
silently; core/models/Plausible.hpp holds the bounds)."""
import pytest
from yade import O, utils

import viscbridge
import viscbridge.liquid as liquid
import viscbridge.scenes as scenes


def said(capfd):
    return capfd.readouterr().err


def test_a_viscosity_in_mpa_s_is_said(capfd):
    said(capfd)
    viscbridge.engines(viscosity=5000)
    err = said(capfd)
    assert 'viscosity=5000 Pa·s is above 1000 Pa·s' in err and 'in mPa·s it would be 5 Pa·s' in err
    viscbridge.engines(viscosity=500)
    assert 'viscosity' not in said(capfd)


def test_a_drum_of_metre_spheres_is_said_and_built(capfd):
    said(capfd)
    d = scenes.drum(radius=1, n=20)
    err = said(capfd)
    assert 'drum: radius=1 m is above 0.1 m' in err and 'the drum is 40 m across' in err
    O.run(5, True)  # the scene's own check says it once, not again
    assert 'radius' not in said(capfd) and len(d.spheres) == 20


def test_a_drum_slower_than_one_rpm_is_said(capfd):
    said(capfd)
    scenes.drum(radius=1e-3, drumRadius=10e-3, n=20, rpm=0.5)
    assert 'it turns at 0.5 rpm, slower than any granulation drum' in said(capfd)
    scenes.drum(radius=1e-3, drumRadius=10e-3, n=20)  # Fr 0.05: 67 rpm
    assert 'rpm' not in said(capfd)


def test_a_film_larger_than_its_sphere_is_said_once(capfd):
    d = scenes.drum(radius=1e-3, drumRadius=10e-3, n=20, wetFraction=0)
    a, b, c = d.spheres[:3]
    said(capfd)
    liquid.set_film([a, b], 2)  # 2 m³ on 1 mm spheres
    liquid.add([c], 1.0)
    err = said(capfd)
    assert err.count('more than its own volume') == 1 and 'set_film: body #%d gets a film of 2 m³' % a in err
    assert liquid.film(a) == 2  # legal: set as asked


def test_the_scene_check_says_a_large_sphere_built_by_hand(capfd):
    O.bodies.append([utils.wall(0, axis=2), utils.sphere((0, 0, 0.5), 0.5)])
    O.engines = viscbridge.engines(viscosity=1.0)
    said(capfd)
    O.run(3, True)
    assert 'Body #1: Sphere.radius=0.5 m is above 0.1 m' in said(capfd)
