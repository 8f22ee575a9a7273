"""Energy accounting of a small wet settling run: with NewtonIntegrator's kinetic and gravWork and
the law's dissipation and elastic terms, O.energy.total() stays within 1 % of |gravWork|."""

import pytest
from yade import O, utils

import viscbridge
from wetpairs import R, RHO, material, wet_box


@pytest.mark.parametrize('tangential', ['slip', 'goldman'])
def test_wet_settling_energy_balance(tangential):
    """At the time stepper's default safety; the viscous work is accounted with the velocities
    before and after each step, so the balance does not degrade with Δt (physics.md §6)."""
    wet_box(tangential=tangential)
    while O.time < 0.03:
        O.run(2000, True)
    E = dict(O.energy.items())
    assert E['gravWork'] < 0 and E['viscDissipNormal'] > 0 and E['viscDissipTangential'] > 0
    assert min(E['viscDissipNormal'], E['viscDissipTangential'], E['viscDissipRotational'], E['plastDissip']) >= 0
    assert sum(1 for i in O.interactions if i.phys.bridge) > 20  # a wet packing formed
    assert abs(O.energy.total()) <= 0.01 * abs(E['gravWork']), E


@pytest.mark.parametrize('dt, bound', [(8.65e-6, 0.03), (1e-6, 3e-3), (1e-7, 3e-4)])
def test_contact_damping_energy_is_first_order_in_dt(dt, bound):
    """One sphere bouncing on a wall at 0.1 m/s, en = 0.5, dry: the contact dashpots' work is booked
    with the incident velocity (physics.md §6), so the balance is off by O(Δt) — 2.4 % of the impact
    energy at the stepper's collision step, ten times less for each tenth of it — and the bounce
    loses 1 − en² of its kinetic energy."""
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, 0.6e-3), R, material=mat)])
    O.bodies[1].state.vel = (0, 0, -0.1)
    O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=0.0, en=0.5, timeStepper=False, guard=False)
    O.dt = dt
    O.trackEnergy = True
    O.run(1, True)
    ke0, total0 = O.energy['kinetic'], O.energy.total()
    O.run(int(2e-3 / dt), True)
    assert O.bodies[1].state.vel[2] > 0 and O.energy['elastPotential'] == 0  # bounced, out of contact
    assert O.energy['kinetic'] / ke0 == pytest.approx(0.25, abs=0.01)
    drift = (O.energy.total() - total0) / ke0
    assert abs(drift) < bound
