"""Bridge life (physics.md §2) and continuity of the normal force through contact (P6)."""
import math

import pytest
from yade import O

from wetpairs import R, Recorder, gap_and_approach, head_on_pair

pytestmark = pytest.mark.slow  # long pair runs


def real():
    return O.interactions.has(0, 1) and O.interactions[0, 1].isReal


def test_rupture_at_lian_distance():
    theta, volume = 0.5, 0.02 * 4 / 3 * math.pi * R ** 3
    s_rup = (1 + theta / 2) * volume ** (1 / 3)  # P11
    head_on_pair(1e-4 * R, -3.0, viscosity=0.01, bridgeVolume=volume, contactAngle=theta, tangentialModel='none')
    O.dt = 2e-9
    rec = Recorder(lambda: (gap_and_approach()[0], real()))
    O.run(1, True)
    assert O.interactions[0, 1].phys.sRup == pytest.approx(s_rup, rel=1e-12)
    while real():
        O.run(100, True)
    held = [s for s, alive in rec.rows if alive]
    step = 3.0 * O.dt  # gap change per step
    assert s_rup - step <= max(held) <= s_rup + step  # kept up to S_rup
    first_gone = next(s for s, alive in rec.rows if not alive)
    assert first_gone <= s_rup + 2 * step  # and erased in the step after crossing it


def test_no_bridge_reforms_after_rupture_until_contact():
    head_on_pair(1e-4 * R, -3.0, viscosity=0.01, bridgeVolumeRel=0.001, tangentialModel='none')
    O.dt = 2e-9
    O.run(1, True)
    while real():
        O.run(100, True)
    # move them back to a small gap (within formationDistance of the first bridge) without contact
    O.bodies[0].state.vel = O.bodies[1].state.vel = (0, 0, 0)
    O.bodies[1].state.pos = (2 * R + 0.5 * 1e-4 * R, 0, 0)
    O.engines[2].physDispatcher.functors[0].formationDistance = 0  # viscBridgeIp2: only contact forms bridges
    O.run(50, True)
    assert not real()


def test_normal_force_is_continuous_through_contact():
    """Kinematic approach at constant speed: the total normal force on body 1 is smooth at S = 0."""
    s_min = 1e-3 * R / 2
    head_on_pair(4 * s_min, 0.01, viscosity=1.0, sMin=s_min, tangentialModel='none')
    for b in O.bodies:
        b.state.blockedDOFs = 'xyzXYZ'  # prescribed velocity
    O.dt = 1e-7
    rec = Recorder(lambda: (O.interactions[0, 1].phys.separation,
                            (O.interactions[0, 1].phys.normalContactForce + O.interactions[0, 1].phys.normalViscousForce)[0]))
    O.run(1200, True)  # contact after 1000 steps
    S = [s for s, _ in rec.rows]
    F = [f for _, f in rec.rows]
    i = next(k for k in range(1, len(S)) if S[k] <= 0 < S[k - 1])
    # the gap moves 1e-9 m per step: a continuous force changes by ~1e-7 of itself per step, a
    # model that switched force laws at contact would jump by a finite fraction
    assert abs(F[i] - F[i - 1]) <= 1e-5 * abs(F[i])
    assert abs(F[i + 1] - F[i]) <= 1e-5 * abs(F[i])
    c_min = 6 * math.pi * 1.0 * (R / 2) ** 2 / s_min
    assert F[i - 1] == pytest.approx(-c_min * 0.01, rel=1e-6)  # viscous at S_min: −C(S_min)·w on body 1
