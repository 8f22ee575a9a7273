"""Energy accounting of a small wet settling run: with NewtonIntegrator's kinetic and gravWork and
the law's dissipation and elastic terms, O.energy.total() stays within 1 % of |gravWork|."""
import random

import pytest
from yade import O, utils

import viscbridge
from viscbridge import criteria
from wetpairs import R, RHO, material


def wet_box(n=40, mu=0.01, tangential='slip', seed=1):
    mat = material(young=1e7, friction=0.4)
    L = 8 * R
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.wall(0, axis=0, material=mat),
                     utils.wall(L, axis=0, material=mat), utils.wall(0, axis=1, material=mat),
                     utils.wall(L, axis=1, material=mat)])
    rng = random.Random(seed)
    placed = []
    while len(placed) < n:
        p = (rng.uniform(R, L - R), rng.uniform(R, L - R), rng.uniform(R, 12 * R))
        if all(sum((a - b) ** 2 for a, b in zip(p, q)) > (2.05 * R) ** 2 for q in placed):
            placed.append(p)
    O.bodies.append([utils.sphere(p, R, material=mat) for p in placed])
    O.engines = viscbridge.engines(guard=False, viscosity=mu, tangentialModel=tangential, normalModel='adamsPerchard')
    O.dt = 0.2 * criteria.rayleigh_time(R, RHO, 1e7, 0.3)  # the time stepper takes over from here
    O.trackEnergy = True


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
