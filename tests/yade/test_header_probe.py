"""The plugin reads a live scene through YADE's C++ headers; every value must equal YADE's own
Python view.  A wrong feature macro or header version shifts member offsets and breaks this."""
import math

import pytest
from yade import O, utils
from yade.wrapper import (FrictMat, ForceResetter, InsertionSortCollider, Bo1_Sphere_Aabb,
                          InteractionLoop, Ig2_Sphere_Sphere_ScGeom, Ip2_FrictMat_FrictMat_FrictPhys,
                          Law2_ScGeom_FrictPhys_CundallStrack, NewtonIntegrator,
                          ViscBridgeHeaderProbe)


def build_scene():
    m1 = O.materials.append(FrictMat(young=3.1e7, poisson=0.27, density=2345., frictionAngle=0.41))
    m2 = O.materials.append(FrictMat(young=4.7e8, poisson=0.19, density=1234., frictionAngle=0.23))
    O.bodies.append([
        utils.sphere((0.1, 0.2, 0.3), 0.011, material=m1),
        utils.sphere((0.1, 0.2, 0.3205), 0.0097, material=m2),
        utils.sphere((0.5, -0.3, 0.7), 0.013, material=m1),
    ])
    O.bodies[0].state.vel = (0.3, -0.2, 0.05)
    O.bodies[1].state.vel = (-0.11, 0.07, -0.4)
    O.bodies[1].state.angVel = (1.5, -2.5, 3.5)
    O.bodies[2].state.angVel = (-0.7, 0.2, 0.9)
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb()]),
        InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                        [Law2_ScGeom_FrictPhys_CundallStrack()]),
        NewtonIntegrator(gravity=(0.3, -1.1, -9.7), damping=0.0),
    ]
    O.dt = 3.7e-6
    O.run(7, True)


def vec_close(a, b):
    return all(math.isclose(x, y, rel_tol=0, abs_tol=1e-14 * max(1.0, abs(y))) for x, y in zip(a, b))


def test_probe_matches_python_view():
    build_scene()
    snap = ViscBridgeHeaderProbe().read()

    assert snap['scene']['dt'] == O.dt == 3.7e-6
    assert snap['scene']['iter'] == O.iter == 7
    assert snap['scene']['time'] == pytest.approx(O.time, rel=1e-15) and O.time > 0

    assert [b['id'] for b in snap['bodies']] == [b.id for b in O.bodies]
    for b in snap['bodies']:
        st = O.bodies[b['id']].state
        assert vec_close(b['pos'], st.pos)
        assert vec_close(b['vel'], st.vel)
        assert vec_close(b['angVel'], st.angVel)
        assert b['mass'] == st.mass and b['mass'] > 0
        assert vec_close(b['inertia'], st.inertia)

    real = [i for i in O.interactions]
    assert len(real) == 1 and len(snap['interactions']) >= 1
    probe_i = {(i['id1'], i['id2']): i for i in snap['interactions']}
    for i in real:
        p = probe_i[(i.id1, i.id2)]
        assert p['isReal'] == i.isReal is True
        assert vec_close(p['normal'], i.geom.normal)
        assert p['penetrationDepth'] == i.geom.penetrationDepth > 0
        assert p['radius1'] == i.geom.refR1 == 0.011
        assert p['radius2'] == i.geom.refR2 == 0.0097
        assert vec_close(p['contactPoint'], i.geom.contactPoint)

    mats = {m['id']: m for m in snap['materials']}
    for m in O.materials:
        p = mats[m.id]
        assert (p['young'], p['poisson'], p['density'], p['frictionAngle']) == \
               (m.young, m.poisson, m.density, m.frictionAngle)
    assert mats[1]['young'] == 4.7e8
