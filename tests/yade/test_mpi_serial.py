"""viscbridge.mpi in one process (no yade.mpy): the helpers return the serial values, and decompose()
splits a scene into equal slabs and leaves the walls to the master.  (On several ranks:
tests/system/test_mpi.py.)"""
import pytest
from yade import O
import yade.wrapper as yw

import viscbridge.mpi


def test_decompose_makes_equal_slabs_and_leaves_walls_to_the_master():
    import viscbridge.scenes as scenes
    scenes.settling(n=30, viscosity=0.1, seed=2)
    counts = viscbridge.mpi.decompose(axis=0, workers=3)
    assert counts == [10, 10, 10]
    spheres = sorted((b for b in O.bodies if isinstance(b.shape, yw.Sphere)), key=lambda b: b.state.pos[0])
    assert [b.subdomain for b in spheres] == sorted(b.subdomain for b in spheres)  # slabs along x
    assert all(b.subdomain == 0 for b in O.bodies if isinstance(b.shape, yw.Wall))


@pytest.mark.parametrize('kw', [dict(axis=3), dict(workers=-1), dict(workers=1.5)])
def test_decompose_rejects_bad_arguments(kw):
    import viscbridge.scenes as scenes
    scenes.settling(n=10, viscosity=0.1)
    with pytest.raises(ValueError, match=list(kw)[0]):
        viscbridge.mpi.decompose(**kw)


def test_serial_helpers_are_plain():
    """Without mpy (one process) rank/ranks/decompose/energy are the serial values."""
    import viscbridge.scenes as scenes
    scenes.settling(n=10, viscosity=0.1)
    O.run(20, True)
    assert viscbridge.mpi.ranks() == 1 and viscbridge.mpi.rank() == 0
    assert viscbridge.mpi.decompose() == []
    assert viscbridge.mpi.energy() == dict(O.energy.items())
    assert viscbridge.mpi.energy_total() == pytest.approx(O.energy.total(), rel=1e-15)
