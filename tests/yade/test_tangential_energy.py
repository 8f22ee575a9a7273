"""Frozen gap, no other force: a sphere next to a wall starts sliding without spin (physics.md §2).

'slip' and 'goldman' are dissipative: the kinetic energy never increases and
KE + dissipated energy = KE₀ to O(Δt).  'washino' (the paper's P7) is not: the sphere ends with
(2.5/(2.5+k))²(1 + 0.4k²) times its initial energy, k = C_T/C_R (×1.0886 at S = 1e-3 r)."""
import math

import pytest
from yade import O, utils

import viscbridge
from wetpairs import R, Recorder, material, sphere_mass

GAP = 1e-3 * R
MU = 1.0


def sliding_sphere(model):
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, R + GAP), R, material=mat)])
    ball = O.bodies[1].state
    ball.blockedDOFs = 'z'  # the gap stays frozen
    ball.vel = (0.01, 0, 0)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), timeStepper=False, guard=False, viscosity=MU,
                                   sMin=1e-5 * R, normalModel='none', tangentialModel=model,
                                   formationDistance=2 * GAP, minRadius=R)
    O.trackEnergy = True
    m = sphere_mass()
    c_t = 6 * math.pi * MU * R * (8 / 15 * math.log(1 / 1e-3) + 0.9588)  # P8 at S = 1e-3 r (r̄ = r)
    O.dt = 0.005 * m / c_t
    inertia = 0.4 * m * R * R
    rec = Recorder(lambda: 0.5 * m * ball.vel.squaredNorm() + 0.5 * inertia * ball.angVel.squaredNorm())
    ke0 = 0.5 * m * 0.01 ** 2
    O.run(8000, True)
    return ke0, rec.rows


@pytest.mark.parametrize('model', ['slip', 'goldman'])
def test_dissipative_models_never_gain_kinetic_energy(model):
    ke0, ke = sliding_sphere(model)
    assert O.interactions[0, 1].phys.bridge
    assert all(b <= a * (1 + 1e-12) for a, b in zip([ke0] + ke, ke)), 'kinetic energy increased'
    assert ke[-1] < 0.9 * ke0
    dissipated = O.energy['viscDissipTangential'] + O.energy['viscDissipRotational']
    assert O.energy['viscDissipRotational'] >= 0
    assert ke[-1] + dissipated == pytest.approx(ke0, rel=0.01)  # KE + ∫(−P)dt = KE₀ to O(Δt)


def test_washino_gains_kinetic_energy_as_documented():
    ke0, ke = sliding_sphere('washino')
    L = math.log(1 / 1e-3)
    k = (8 / 15 * L + 0.9588) / (2 / 15 * L + 0.2526)  # C_T/C_R
    expected = (2.5 / (2.5 + k)) ** 2 * (1 + 0.4 * k * k)
    assert expected == pytest.approx(1.0886, abs=5e-4)
    assert ke[-1] / ke0 == pytest.approx(expected, rel=0.01)
    assert O.energy['viscDissipRotational'] < 0  # where the energy comes from
