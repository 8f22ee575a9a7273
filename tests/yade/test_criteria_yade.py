"""viscbridge.criteria against YADE's own numbers: the Rayleigh-wave time of utils.RayleighWaveTimeStep."""
import pytest

from viscbridge import criteria as C

R, RHO, E, NU = 0.5e-3, 2500.0, 1e7, 0.3   # physics.md "orders of magnitude"


def test_rayleigh_equals_yade():
    from yade import O, utils
    from yade.wrapper import FrictMat
    mat = O.materials.append(FrictMat(young=E, poisson=NU, density=RHO))
    O.bodies.append(utils.sphere((0, 0, 0), R, material=mat))
    assert C.rayleigh_time(R, RHO, E, NU) == pytest.approx(utils.RayleighWaveTimeStep(), rel=1e-12)
