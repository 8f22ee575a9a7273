"""ViscBridgeForceSum (docs/architecture.md, "Bit-identical on any number of threads"): after the
interaction loop it adds the law's forces per body, in the order of the partners' ids; without it
the law adds them itself; misplaced, it says where it belongs instead of losing forces."""
import pytest
from yade import O
import yade.wrapper as yw

import viscbridge.scenes as scenes


def settle(steps=400):
    scenes.settling(n=40, viscosity=0.1, seed=3, initialSpeed=0.3, cloudFraction=0.25, width=5e-3)
    O.run(steps, True)


def forces():
    return [(tuple(O.forces.f(b.id)), tuple(O.forces.t(b.id))) for b in O.bodies]


def test_the_summed_forces_are_the_laws_own():
    """One step with the engine and the same step with it dead (the law adds its forces itself):
    the same forces on every body to rounding (a sum in another order), many of them non-zero."""
    settle()
    O.saveTmp('before')
    O.step()
    summed = forces()
    O.loadTmp('before')
    next(e for e in O.engines if isinstance(e, yw.ViscBridgeForceSum)).dead = True
    O.step()
    direct = forces()
    loaded = [k for k, (f, t) in enumerate(summed) if any(abs(x) > 0 for x in f)]
    assert len(loaded) > 20
    scale = max(abs(x) for f, t in summed for x in f)
    for (fs, ts), (fd, td) in zip(summed, direct):
        assert fs == pytest.approx(fd, abs=1e-12 * scale)


def test_a_misplaced_force_sum_names_where_it_belongs(run_error):
    settle(10)
    engines = [e for e in O.engines if not isinstance(e, yw.ViscBridgeForceSum)]
    loop = next(i for i, e in enumerate(engines) if isinstance(e, yw.InteractionLoop))
    O.engines = engines[:loop] + [yw.ViscBridgeForceSum()] + engines[loop:]
    message = run_error(1)
    assert 'ViscBridgeForceSum' in message and 'after InteractionLoop and before NewtonIntegrator' in message
