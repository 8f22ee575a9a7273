"""With every viscous effect off, the law must follow YADE's own Hertz–Mindlin law:
Ip2_FrictMat_FrictMat_MindlinPhys + Law2_ScGeom_MindlinPhys_Mindlin, within 1e-9 relative."""
import pytest
from yade import O, utils
from yade.wrapper import (ForceResetter, InsertionSortCollider, Bo1_Sphere_Aabb, Bo1_Wall_Aabb, InteractionLoop,
                          Ig2_Sphere_Sphere_ScGeom, Ig2_Wall_Sphere_ScGeom, Ip2_FrictMat_FrictMat_MindlinPhys,
                          Law2_ScGeom_MindlinPhys_Mindlin, NewtonIntegrator, Ip2_FrictMat_FrictMat_ViscBridgePhys,
                          Law2_ScGeom_ViscBridgePhys_HertzViscous)

from wetpairs import R, Recorder, material

pytestmark = pytest.mark.slow  # long pair runs, step by step against YADE

LAWS = {
    'yade': lambda: ([Ip2_FrictMat_FrictMat_MindlinPhys()], [Law2_ScGeom_MindlinPhys_Mindlin()]),
    'viscbridge, dry': lambda: ([Ip2_FrictMat_FrictMat_ViscBridgePhys(viscosity=0)], [Law2_ScGeom_ViscBridgePhys_HertzViscous()]),
    'viscbridge, models off': lambda: ([Ip2_FrictMat_FrictMat_ViscBridgePhys(viscosity=5.0, normalModel='none', tangentialModel='none')],
                                       [Law2_ScGeom_ViscBridgePhys_HertzViscous()]),
}


def trajectory(law, build, steps, gravity):
    O.reset()
    build()
    ip2, law2 = LAWS[law]()
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()], ip2, law2),
                 NewtonIntegrator(gravity=gravity, damping=0)]
    O.dt = 2e-7
    rec = Recorder(lambda: [tuple(b.state.pos) + tuple(b.state.vel) + tuple(b.state.angVel) for b in O.bodies])
    O.run(steps, True)
    return rec.rows


def oblique_collision():
    mat = material(young=1e8, friction=0.4)
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((2.01 * R, 0.6 * R, 0.1 * R), 0.8 * R, material=mat)])
    O.bodies[0].state.vel = (0.8, 0.05, 0.0)
    O.bodies[0].state.angVel = (10, -40, 25)


def resting_on_wall():
    mat = material(young=1e7, friction=0.5)
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, 0.999 * R), R, material=mat)])
    O.bodies[1].state.vel = (0.01, 0, 0)  # rolls and slides while it settles


def max_relative_difference(a, b):
    worst = 0.0
    for ra, rb in zip(a, b):
        for body_a, body_b in zip(ra, rb):
            scale = max(max(abs(x) for x in body_b), 1e-30)
            worst = max(worst, max(abs(x - y) for x, y in zip(body_a, body_b)) / scale)
    return worst


@pytest.mark.parametrize('law', ['viscbridge, dry', 'viscbridge, models off'])
@pytest.mark.parametrize('case,steps,gravity', [(oblique_collision, 3000, (0, 0, 0)), (resting_on_wall, 20000, (0, 0, -9.81))])
def test_trajectories_match_yade_mindlin(law, case, steps, gravity):
    reference = trajectory('yade', case, steps, gravity)
    ours = trajectory(law, case, steps, gravity)
    assert len(ours) == len(reference) >= steps - 1
    moved = max(abs(x) for x in reference[-1][-1][3:6])
    assert moved > 0  # the scene does something
    assert max_relative_difference(ours, reference) <= 1e-9
