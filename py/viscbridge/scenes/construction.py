"""Building a settling scene in O (:func:`settling`): the arguments checked, a random cloud of
spheres placed in a walled (or periodic) column above a floor, optional initial velocities, the
engines of :func:`viscbridge.engines` and the starting time step.
"""
import math

from yade import O, plot, utils
from yade import pack
import yade.wrapper as yw

from .. import _checks, criteria, liquid
from ..engine_list import ENGINE_INTEGRATIONS, bridge_parameters, check_accuracy, engines
from .runner import Settling

__all__ = ['settling']


def settling(n=300, radius=0.5e-3, sizeRatio=1.0, density=2500.0, young=1e7, poisson=0.3, friction=0.5,
             viscosity=1.0, dt=None, safety=None, seed=1, width=None, height=None, periodic=False,
             gravity=9.81, initialSpeed=0.0, integration=None, trackEnergy=True, guard=True,
             cloudFraction=0.2, filmRel=0.0, accuracy=None, **effects):
    """Build a settling scene in O (which is reset) and return a :class:`Settling` handle.

    n spheres of mean radius `radius` [m] (radii uniform in a range with max/min = sizeRatio, 1–5)
    are placed at random, without contact, in a column of square cross-section `width` (default
    10 mean diameters) and height `height` (default: a loose cloud of solid fraction `cloudFraction`,
    at most 0.27, beyond which random placement fails), above a
    floor.  The sides are walls and the floor a wall; with periodic=True the column is periodic in
    x and y and the floor a layer of fixed spheres (a periodic cell allows no infinite wall).  They
    settle under `gravity` [m/s²] through liquid of `viscosity` [Pa·s]; the other liquid and model
    parameters (sMin/sMinRel, bridgeVolume/bridgeVolumeRel, contactAngle, normalModel,
    tangentialModel, capillaryModel, surfaceTension, formationDistance, en) are those of
    :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys`.

    dt: a fixed time step [s], or None for ViscBridgeTimeStepper with `safety` (None: its default).
    accuracy: a tolerance on the run's relative error, in (0, 1), or None: see viscbridge.engines
        (with it, integration defaults to 'auto': the stepper picks the scheme and dt).
    integration: 'explicit', 'implicit' or 'auto' (default: 'auto' with `accuracy`, else 'explicit').
    initialSpeed: random initial velocities of this magnitude [m/s] (to start with motion).
    filmRel: with liquidModel='film', every sphere's film as a fraction of its volume (0: dry; add
        liquid later with :mod:`viscbridge.liquid`).
    seed: random seed of the positions (and velocities).
    """
    if integration is None:
        integration = 'explicit' if accuracy is None else 'auto'
    _check_settling_args(n, radius, sizeRatio, density, young, poisson, friction, dt, safety, seed, width, height,
                         periodic, gravity, initialSpeed, integration, trackEnergy, guard)
    check_accuracy(accuracy, dt is None, 'settling')
    _checks.in_range('settling', 'cloudFraction', cloudFraction, 0, 0.27, lo_open=True)
    _checks.in_range('settling', 'filmRel', filmRel, 0, 1)
    if filmRel > 0 and effects.get('liquidModel') != 'film':
        raise ValueError("settling: filmRel=%r needs liquidModel='film' (with 'fixed' bridges the films are not used)" % (filmRel,))
    n, seed = int(n), int(seed)
    ip2_args, rest = bridge_parameters(viscosity=viscosity, **effects)
    if rest:
        raise ValueError('settling: unknown parameter(s) %s' % ', '.join(sorted(rest)))

    O.reset()
    plot.reset()
    fuzz = (sizeRatio - 1.0) / (sizeRatio + 1.0)
    r_min = radius * (1 - fuzz)
    width = width or 20 * radius
    height = height or _cloud_height(n, radius, fuzz, width, cloudFraction)
    mat = O.materials.append(yw.FrictMat(young=young, poisson=poisson, density=density, frictionAngle=friction))
    walls, ids = _column(n, radius, fuzz, width, height, periodic, seed, mat)
    if initialSpeed > 0:
        _perturb(ids, initialSpeed, seed)

    O.engines = engines(gravity=(0, 0, -gravity), integration=integration, timeStepper=dt is None, safety=safety,
                        guard=guard, minRadius=r_min, accuracy=accuracy, **ip2_args)
    # with the stepper, start from the collision bound: it only lets dt grow gradually
    O.dt = 0.2 * criteria.rayleigh_time(r_min, density, young, poisson) if dt is None else dt
    O.trackEnergy = trackEnergy
    if filmRel > 0:
        liquid.set_film(ids, [filmRel * 4 / 3 * math.pi * O.bodies[i].shape.radius ** 3 for i in ids])
    params = dict(n=n, radius=radius, sizeRatio=sizeRatio, density=density, young=young, poisson=poisson,
                  friction=friction, dt=dt, safety=safety, seed=seed, width=width, height=height,
                  periodic=periodic, gravity=gravity, initialSpeed=initialSpeed, integration=integration,
                  accuracy=accuracy, cloudFraction=cloudFraction, filmRel=filmRel, sMin=0.0, sMinRel=1e-3)
    params.update(ip2_args)
    return Settling(params, walls, {i: O.bodies[i].state.pos[2] for i in ids})


def _check_settling_args(n, radius, sizeRatio, density, young, poisson, friction, dt, safety, seed, width, height,
                         periodic, gravity, initialSpeed, integration, trackEnergy, guard):
    f = 'settling'
    _checks.integer(f, 'n', n, minimum=1)
    _checks.integer(f, 'seed', seed)
    for name, value, unit in (('radius', radius, ' [m]'), ('density', density, ' [kg/m³]'), ('young', young, ' [Pa]'),
                              ('gravity', gravity, ' [m/s²]')):
        _checks.positive(f, name, value, unit)
    _checks.in_range(f, 'sizeRatio', sizeRatio, 1, 5)
    _checks.in_range(f, 'poisson', poisson, -1, 0.5, lo_open=True, hi_open=True)
    _checks.non_negative(f, 'friction', friction, ' [rad]')
    _checks.non_negative(f, 'initialSpeed', initialSpeed, ' [m/s]')
    for name, value, unit in (('dt', dt, ' [s]'), ('width', width, ' [m]'), ('height', height, ' [m]')):
        if value is not None:
            _checks.positive(f, name, value, unit + ' or None')
    if safety is not None:
        _checks.in_range(f, 'safety', safety, 0, 1, lo_open=True)
    for name, value in (('periodic', periodic), ('trackEnergy', trackEnergy), ('guard', guard)):
        _checks.boolean(f, name, value)
    _checks.choice(f, 'integration', integration, ENGINE_INTEGRATIONS)



def _cloud_height(n, radius, fuzz, width, cloudFraction):
    """The height of a loose cloud of n spheres (radii radius·(1 ± fuzz)) at solid fraction
    `cloudFraction` in a column of side `width`, at least 8 radii."""
    mean_volume = 4.0 / 3.0 * math.pi * radius ** 3 * (1 + fuzz ** 2)
    return max(n * mean_volume / (cloudFraction * width * width), 8 * radius)


def _column(n, radius, fuzz, width, height, periodic, seed, mat):
    """The cloud placed at random in the column, lifted just clear of the floor; the floor and side
    walls (or, periodic, a floor of fixed spheres) added first.  Returns (wall ids, sphere ids)."""
    sp = pack.SpherePack()
    if periodic:
        O.periodic = True
        O.cell.setBox(width, width, 4 * height)
        placed = sp.makeCloud((0, 0, 0), (width, width, height), rMean=radius, rRelFuzz=fuzz, num=n, periodic=True, seed=seed)
    else:
        placed = sp.makeCloud((0, 0, 0), (width, width, height), rMean=radius, rRelFuzz=fuzz, num=n, seed=seed)
    if placed < n:
        raise ValueError('settling: only %d of n=%d spheres fit in width=%g m × height=%g m; allowed: a larger '
                         'width or height' % (placed, n, width, height))
    if periodic:
        walls, floor_r = _floor_of_spheres(width, radius * (1 - fuzz), mat)
        lift = floor_r + 1.01 * radius * (1 + fuzz)  # the periodic cloud's own z range starts at 0
    else:
        walls = [O.bodies.append(utils.wall(0, axis=2, sense=1, material=mat))]
        walls += [O.bodies.append(utils.wall(p, axis=a, material=mat)) for a in (0, 1) for p in (0, width)]
        lift = 0.01 * radius
    ids = sp.toSimulation(material=mat)
    if periodic:  # toSimulation() made the cell the cloud's own periodic box: give it its full height back
        O.cell.setBox(width, width, 4 * height)
    for i in ids:
        O.bodies[i].state.pos += (0, 0, lift)
    return walls, ids


def _perturb(ids, speed, seed):
    """Random initial velocities of magnitude `speed` [m/s] (directions from `seed`)."""
    import random
    rng = random.Random(seed)
    for i in ids:
        v = [rng.gauss(0, 1) for _ in range(3)]
        norm = math.sqrt(sum(x * x for x in v)) or 1.0
        O.bodies[i].state.vel = tuple(speed * x / norm for x in v)


def _floor_of_spheres(width, radius, material):
    """A square lattice of fixed spheres at z = 0 covering a periodic cell of side `width`: a floor a
    periodic cell allows (YADE's collider cannot take an infinite wall inside a periodic cell).
    Spacing 2r with r ≤ `radius`, so the lattice tiles the cell exactly and its holes (0.41 r) let
    no particle of radius ≥ `radius` through.  Returns (ids, radius used)."""
    k = max(2, int(math.ceil(width / (2 * radius))))
    r = width / (2 * k)
    ids = []
    for i in range(k):
        for j in range(k):
            ids.append(O.bodies.append(utils.sphere(((i + 0.5) * 2 * r, (j + 0.5) * 2 * r, 0), r, fixed=True, material=material)))
    return ids, r

