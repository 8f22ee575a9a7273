"""Small scenes for the physics tests: two spheres, or a sphere and a wall/facet, in YADE's O.

Lengths follow physics.md §5: r = 0.5 mm, ρ = 2500 kg/m³ (A = 6πμ r̄²/m* = 1.8 μ for equal
spheres, 3.6 μ against a wall).
"""
import math
import random

from yade import O, utils
from yade.wrapper import FrictMat, PyRunner

import viscbridge
from viscbridge import criteria

R = 0.5e-3
RHO = 2500.0


def sphere_mass(r=R, rho=RHO):
    return rho * 4.0 / 3.0 * math.pi * r ** 3


def material(young=1e7, poisson=0.3, friction=0.5):
    return O.materials.append(FrictMat(young=young, poisson=poisson, density=RHO, frictionAngle=friction))


def decay_time_pair(mu, s_min, r=R):
    """t_v of P12 for two equal spheres: (4/9) ρ r S_min / μ."""
    return 4.0 / 9.0 * RHO * r * s_min / mu


def decay_time_wall(mu, s_min, r=R):
    """t_v of P12 for a sphere against a wall: (2/9) ρ r S_min / μ."""
    return 2.0 / 9.0 * RHO * r * s_min / mu


def head_on_pair(gap, approach_speed, gravity=(0, 0, 0), young=1e7, **effects):
    """Two equal spheres on the x axis at surface gap `gap`, approaching at `approach_speed`
    (negative: separating), with the bridge already formed (formationDistance covers the gap)."""
    mat = material(young=young)
    O.bodies.append([utils.sphere((0, 0, 0), R, material=mat), utils.sphere((2 * R + gap, 0, 0), R, material=mat)])
    O.bodies[0].state.vel = (0.5 * approach_speed, 0, 0)
    O.bodies[1].state.vel = (-0.5 * approach_speed, 0, 0)
    effects.setdefault('formationDistance', 1.5 * abs(gap) + 1e-12)
    O.engines = viscbridge.engines(gravity=gravity, timeStepper=False, guard=False, minRadius=R, **effects)


def gap_and_approach():
    """(S, w) now: S from the positions, w = −dS/dt from the stored velocities."""
    b0, b1 = O.bodies[0].state, O.bodies[1].state
    d = b1.pos - b0.pos
    n = d / d.norm()
    return d.norm() - 2 * R, (b0.vel - b1.vel).dot(n)


class Recorder:
    """Records f() after every step through a PyRunner; `rows` holds the values."""

    def __init__(self, f, period=1):
        self.f, self.rows = f, []
        O.engines = O.engines + [PyRunner(iterPeriod=period, command='import wetpairs; wetpairs._active(%d)' % id(self))]
        _RECORDERS[id(self)] = self


_RECORDERS = {}


def _active(key):
    rec = _RECORDERS[key]
    rec.rows.append(rec.f())


def crossing(xs, ys, x0):
    """y at the first crossing of xs through x0 (linear interpolation); None if it never crosses."""
    for i in range(1, len(xs)):
        if (xs[i - 1] - x0) * (xs[i] - x0) <= 0 and xs[i] != xs[i - 1]:
            t = (x0 - xs[i - 1]) / (xs[i] - xs[i - 1])
            return ys[i - 1] + t * (ys[i] - ys[i - 1])
    return None


def wet_box(n=40, mu=0.01, tangential='slip', seed=1, **engine_options):
    """n spheres dropped at random into a walled box 8 r wide (a wet settling run in small)."""
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
    O.engines = viscbridge.engines(guard=False, viscosity=mu, tangentialModel=tangential, normalModel='adamsPerchard', **engine_options)
    O.dt = 0.2 * criteria.rayleigh_time(R, RHO, 1e7, 0.3)  # the time stepper takes over from here
    O.trackEnergy = True
