"""A wet granulation drum (:func:`drum`): a horizontal cylinder of facets turned by YADE's
RotationEngine, partly filled with spheres, some of them wetted with a viscous binder.

The regime is set by a few numbers (docs/drum.md): the Froude number Fr = ω²R_drum/g (rolling and
cascading below ~0.1, cataracting above, centrifuging at 1); the binder — how many particles carry
it and how much (`wetFraction`, `filmRel`) and the least liquid a bridge forms from
(`minBridgeRel`); whether the drum wall wets (`wetWalls`); and the time a bridge takes to be pulled
apart, t_pull ≈ (9/8)·μ/(ρ g r)·ln(S_rup/S_min), against the time of a revolution.  Defaults: dry
walls, 15 % of the spheres wetted with 2 % of their volume, bridges of 0.2–1 % of a particle's
volume, μ = 1 Pa·s with 1 mm spheres (t_pull ≈ 0.3 s, a revolution 1.3 s in the default drum),
Fr = 0.05 — the bed cascades, agglomerates grow where wet particles meet and break where the flow
pulls them apart.
A wetted drum wall at these viscosities carries the whole bed round as one rigid lump.
"""
import json
import math

from yade import O, pack, plot, utils
from yade import Quaternion
import yade.wrapper as yw
from yade import geom

from .. import _checks, _registry, liquid
from .._yade_run import run_until
from ..engine_list import bridge_parameters, check_accuracy, engines

__all__ = ['drum', 'Drum', 'UNITS']

G = 9.81
DEFAULT_FROUDE = 0.05  # the drum's speed when neither froude nor rpm is given
_TAG = 'viscbridge.drum'  # the O.tags entry of a drum's parameters (Drum.current)

#: The unit of each parameter of :func:`drum` ('' for a number without unit or a name); the Ip2's
#: parameters passed through take theirs from the C++ table (``_registry.PARAMETERS``).
UNITS = dict(radius='m', drumRadius='m', length='m', fill='', n='', froude='', rpm='1/min', viscosity='Pa·s',
             liquidModel='', wetFraction='', filmRel='', minBridgeRel='', wetWalls='', integration='', accuracy='',
             density='kg/m³', young='Pa', poisson='', friction='rad', wallFriction='rad', segments='', seed='')


class Drum:
    """A drum scene living in O (see :func:`drum`): ``params`` (every parameter it was built with,
    the speed as both ``froude`` and ``rpm``), ``units`` (their units), ``omega`` [rad/s],
    ``spheres`` and ``facets`` (body ids), ``rotation`` (its RotationEngine)."""

    def __init__(self, params, omega, spheres, facets, rotation):
        self.params, self.omega, self.spheres, self.facets, self.rotation = params, omega, spheres, facets, rotation
        self._remember()

    def _remember(self):
        """The parameters in O.tags, which are saved with the scene: what current() finds after O.load."""
        O.tags[_TAG] = json.dumps(self.params)

    @classmethod
    def current(cls):
        """The handle of the drum in O: after ``O.load`` of a saved drum (in this process or another),
        ``Drum.current().run(revolutions=...)`` goes on turning it and ``.spray(...)`` sprays it.  The
        parameters are those it was built with (and its last spray's); the spheres are O's dynamic ones."""
        text = dict(O.tags).get(_TAG)
        rotation = [e for e in O.engines if isinstance(e, yw.RotationEngine)]
        if text is None or len(rotation) != 1:
            raise RuntimeError('Drum.current: O holds no drum made by viscbridge.scenes.drum (none was built since O.reset, '
                               'or the scene loaded is not one)')
        params = json.loads(text)
        spheres = [b.id for b in O.bodies if b.dynamic and isinstance(b.shape, yw.Sphere)]
        return cls(params, rotation[0].angularVelocity, spheres, list(rotation[0].ids), rotation[0])

    @property
    def units(self):
        """The unit of each of ``params`` ('' for none): what a record of the run writes beside it."""
        return {k: UNITS[k] if k in UNITS else _registry.PARAMETERS.get(k, {}).get('unit', '') for k in self.params}

    @property
    def period(self):
        """Time of one revolution [s]."""
        return 2 * math.pi / self.omega

    def revolutions(self):
        """Revolutions turned so far."""
        return O.time / self.period

    def _require_current(self, func):
        """Refuse a handle whose drum is no longer O's scene (O reset, or another scene built since)."""
        turning = any(isinstance(e, yw.RotationEngine) and list(e.ids) == self.facets for e in O.engines)
        if not turning or sum(1 for b in O.bodies if b.dynamic) != len(self.spheres):
            raise RuntimeError('%s: this drum is no longer the scene in O (O was reset, or another scene was built or '
                               'loaded since); build it again with viscbridge.scenes.drum(...)' % func)

    def run(self, revolutions=None, duration=None):
        """Turn the drum by `revolutions` (or for `duration` [s] of simulated time); blocks."""
        self._require_current('Drum.run')
        if (revolutions is None) == (duration is None):
            raise ValueError('Drum.run: give exactly one of revolutions=... or duration=... [s]')
        if revolutions is not None:
            duration = _checks.positive('Drum.run', 'revolutions', revolutions) * self.period
        else:
            duration = _checks.positive('Drum.run', 'duration', duration, ' [s]')
        run_until(O.time + duration)

    def spray(self, volumeRel, revolutions=1.0, start=None, dropletRel=0.0, zone=None, nozzle=(0, 0, -1), maxFilmRel=0.1,
              seed=None, label='drumSpray'):
        """Spray binder onto the bed as the drum turns: `volumeRel` × the particles' volume in all,
        at a constant rate over `revolutions` revolutions from revolution `start` on (default: now;
        a start already past is refused), with liquidModel='film'.  Droplets fall along `nozzle` (default straight down) and land on the
        spheres they meet first — the bed's free surface, wherever the cascade has put it
        (physics.md L6) — inside `zone` (``((xmin, ymin, zmin), (xmax, ymax, zmax))`` [m]; default
        the whole drum); no film beyond `maxFilmRel` of its sphere's volume (L7).  `dropletRel`: 0, a
        fine mist over the whole reached surface; above 0, droplets of that fraction of a mean
        particle's volume, each wetting one sphere (L6b: a droplet near a particle's size wets a spot
        that nucleates a granule; `seed`, default the drum's, fixes where they land).  Appends a
        :yref:`ViscBridgeSpray` to O.engines (saved with the scene) and returns it; its period is
        1/100 revolution.  The drum's ``params`` take the spray's (``sprayRel``, ``sprayRevolutions``,
        ``sprayStart`` [revolutions], ``sprayDropletRel``: the last spray's), for the histories made after it."""
        f = 'Drum.spray'
        self._require_current(f)
        if self.params['liquidModel'] != 'film':
            raise ValueError("Drum.spray: the drum was built with liquidModel=%r; sprayed binder needs liquidModel='film' "
                             '(the liquid lives in the particles\' films)' % self.params['liquidModel'])
        _checks.in_range(f, 'volumeRel', volumeRel, 0, 1, lo_open=True)
        revolutions = _checks.positive(f, 'revolutions', revolutions)
        start = liquid._spray_start(f, 'start', start, self.period, ' revolutions')
        R, L = self.params['drumRadius'], self.params['length']
        box = ((-R, -L / 2, -R), (R, L / 2, R)) if zone is None else zone
        dropletRel = _checks.in_range(f, 'dropletRel', dropletRel, 0, 1)
        particles = math.fsum(4 / 3 * math.pi * O.bodies[i].shape.radius ** 3 for i in self.spheres)
        engine = liquid.spray(volumeRel * particles / (revolutions * self.period), box=box, start=start,
                              end=start + revolutions * self.period, nozzle=nozzle, maxFilmRel=maxFilmRel,
                              dropletVolume=dropletRel * particles / len(self.spheres),
                              seed=self.params['seed'] if seed is None else seed, virtPeriod=self.period / 100, label=label)
        O.engines = O.engines + [engine]
        # the spray among the drum's parameters, named as a drum scan names them: a history made from now on records it
        from ..scan.cases import DRUM_SPRAY_KEYS
        given = dict(volumeRel=volumeRel, revolutions=revolutions, start=start / self.period, dropletRel=dropletRel)
        self.params.update({field: given[argument] for field, argument in DRUM_SPRAY_KEYS.items()})
        self._remember()
        return engine

    def describe(self):
        p = self.params
        return '%d spheres (r=%.3g m), drum R=%.3g m, Fr=%.3g (%.1f rpm), μ=%.3g Pa·s, %s liquid, %s walls, %s' % (
            len(self.spheres), p['radius'], p['drumRadius'], p['froude'], p['rpm'], p['viscosity'], p['liquidModel'],
            'wet' if p['wetWalls'] else 'dry', p['integration'])


def drum(radius=1e-3, drumRadius=None, length=None, fill=0.35, n=None, froude=None, rpm=None, viscosity=1.0,
         liquidModel='film', wetFraction=0.15, filmRel=0.02, minBridgeRel=0.002, wetWalls=False, integration=None,
         accuracy=None, density=2500.0, young=1e7, poisson=0.3, friction=0.5, wallFriction=0.8, segments=32, seed=1,
         **effects):
    """Build a drum in O (which is reset) and return its :class:`Drum` handle.

    Spheres of radius `radius` [m] (up to 10 % smaller) in a drum of radius `drumRadius` (default 20 r) and
    length `length` (default 10 r; flat dry end walls), filled to `fill` of its volume by a bed at
    solid fraction 0.6 (or `n` spheres), dropped into it from a loose cloud.  The drum (`segments`
    segments around, two triangular facets each; friction angle `wallFriction` [rad]) turns about the y axis at the Froude number
    `froude` = ω²R/g (default 0.05) or at `rpm` (one of them).  The liquid: `viscosity` [Pa·s] with `liquidModel` 'film' (a
    fraction `wetFraction` of the spheres, chosen at random, carries a film of `filmRel` of its
    volume; bridges take it from them, :mod:`viscbridge.liquid`, and form only from at least
    `minBridgeRel` of a particle's volume, ViscBridgeLiquid.minBridgeVolume) or 'fixed' (every contact wet);
    `wetWalls` False makes the drum wall dry (no bridge).  Other Ip2 parameters (bridgeVolumeRel,
    normalModel, ...) pass through.  `integration`: 'implicit' (the default: at 1–1000 Pa·s the
    explicit viscous limit would be 10²–10⁵ times the collision step), 'explicit' or 'auto'.
    `accuracy`: a tolerance on the run's relative error instead of a time step from stability alone
    (ViscBridgeTimeStepper.accuracy, docs/timestep.md); with it the default integration is 'auto'.
    """
    f = 'drum'
    radius = _checks.positive(f, 'radius', radius, ' [m]')
    drumRadius = _checks.positive(f, 'drumRadius', 20 * radius if drumRadius is None else drumRadius, ' [m]')
    length = _checks.positive(f, 'length', 10 * radius if length is None else length, ' [m]')
    if drumRadius < 5 * radius or length < 4 * radius:
        raise ValueError('drum: drumRadius=%g m and length=%g m must be at least 5 and 4 particle radii (radius=%g m)'
                         % (drumRadius, length, radius))
    _checks.in_range(f, 'fill', fill, 0, 0.6, lo_open=True)
    _checks.in_range(f, 'wetFraction', wetFraction, 0, 1)
    _checks.in_range(f, 'filmRel', filmRel, 0, 1)
    _checks.in_range(f, 'minBridgeRel', minBridgeRel, 0, 1)
    _checks.in_range(f, 'wallFriction', wallFriction, 0, math.pi / 2)
    _checks.choice(f, 'liquidModel', liquidModel, ('fixed', 'film'))
    _checks.boolean(f, 'wetWalls', wetWalls)
    segments = _checks.integer(f, 'segments', segments, minimum=8)
    check_accuracy(accuracy, True, func=f)
    if rpm is not None and froude is not None:
        raise ValueError('drum: froude=%r and rpm=%r both set the speed; give one of them (neither: froude=%g)' % (froude, rpm, DEFAULT_FROUDE))
    if rpm is not None:
        omega = _checks.positive(f, 'rpm', rpm) * 2 * math.pi / 60
        froude = omega ** 2 * drumRadius / G
    else:
        froude = DEFAULT_FROUDE if froude is None else froude
        omega = math.sqrt(_checks.in_range(f, 'froude', froude, 0, 1, lo_open=True) * G / drumRadius)
    if n is None:
        n = int(round(fill * math.pi * drumRadius ** 2 * length * 0.6 / (4 / 3 * math.pi * radius ** 3)))
    n = _checks.integer(f, 'n', n, minimum=1)
    ip2_args, rest = bridge_parameters(viscosity=viscosity, liquidModel=liquidModel, **effects)
    if rest:
        raise ValueError('drum: unknown parameter(s) %s%s' % (', '.join(sorted(rest)), _checks.suggestion(
            sorted(rest)[0], list(UNITS) + list(_registry.PARAMETERS))))

    O.reset()
    plot.reset()
    _warn_implausible(radius, drumRadius, omega)  # once per scene: this one
    particles = O.materials.append(yw.FrictMat(young=young, poisson=poisson, density=density, frictionAngle=friction))
    shell = O.materials.append(yw.FrictMat(young=young, poisson=poisson, density=density, frictionAngle=wallFriction))
    facets = _shell(drumRadius, length, segments, shell)
    spheres = _bed(n, radius, drumRadius, length, seed, particles)
    if not wetWalls:
        liquid.make_dry(material=O.materials[shell])
    rotation = yw.RotationEngine(ids=facets, rotationAxis=(0, 1, 0), rotateAroundZero=True, zeroPoint=(0, 0, 0),
                                 angularVelocity=omega, label='drumRotation')
    film_args = {} if liquidModel != 'film' else {'minBridgeVolume': minBridgeRel * 4 / 3 * math.pi * radius ** 3}
    if integration is None:
        integration = 'implicit' if accuracy is None else 'auto'
    O.engines = engines(gravity=(0, 0, -G), integration=integration, accuracy=accuracy, minRadius=0.9 * radius,
                        kinematic=[rotation], **film_args, **ip2_args)
    O.dt = 1e-6  # the time stepper takes over
    if liquidModel == 'film' and wetFraction > 0 and filmRel > 0:
        import random
        rng = random.Random(seed)
        wet = sorted(rng.sample(spheres, int(round(wetFraction * len(spheres)))))
        liquid.set_film(wet, [filmRel * 4 / 3 * math.pi * O.bodies[i].shape.radius ** 3 for i in wet])
    params = dict(radius=radius, drumRadius=drumRadius, length=length, fill=fill, n=n, froude=froude,
                  rpm=omega * 60 / (2 * math.pi), viscosity=viscosity, liquidModel=liquidModel, wetFraction=wetFraction,
                  filmRel=filmRel, minBridgeRel=minBridgeRel, wetWalls=wetWalls, integration=integration, accuracy=accuracy, density=density,
                  young=young, poisson=poisson, friction=friction, wallFriction=wallFriction, segments=segments, seed=seed)
    params.update(ip2_args)
    return Drum(params, omega, spheres, facets, rotation)


def _warn_implausible(radius, drumRadius, omega):
    """Sizes and speeds no granulation drum has: likely unit mistakes (YADE's log, once; the drum is built)."""
    largest = _registry.PLAUSIBLE['maxRadius']
    if radius > largest:
        _checks.implausible('radius', 'drum: radius=%g m is above %g m, larger than the particles of any wet granulation '
                                      'run (µm to cm): the drum is %g m across; lengths are in m' % (radius, largest, 2 * drumRadius))
    rpm = omega * 60 / (2 * math.pi)
    if rpm < 1:
        _checks.implausible('rpm', 'drum: it turns at %.3g rpm, slower than any granulation drum (5–60 rpm in the lab, '
                                   '> 1 rpm in production); rpm is in revolutions per minute, froude = ω²R/g' % rpm)


def _shell(drumRadius, length, segments, material):
    """The drum's cylinder of facets (axis y, through the origin) and two flat end walls, all on
    `material`; returns the cylinder's facet ids (the end walls stay still)."""
    # geom.facetCylinder's axis is z: turned a quarter round x it lies along y
    q = Quaternion((1, 0, 0), math.pi / 2)
    facets = O.bodies.append(geom.facetCylinder((0, 0, 0), drumRadius, length, orientation=q, segmentsNumber=segments,
                                                wallMask=4, material=material))
    O.bodies.append([utils.wall(-length / 2, axis=1, sense=1, material=material),
                     utils.wall(length / 2, axis=1, sense=-1, material=material)])
    return facets


def _bed(n, radius, drumRadius, length, seed, material):
    """n spheres (radius ±10 %) on a jittered cubic lattice of spacing 2.3 r in the lower part of the
    drum, lowest first: they fall into a bed as the drum starts to turn."""
    import random
    rng = random.Random(seed)
    pitch, inner = 2.3 * radius, drumRadius - 1.2 * radius
    span = int(inner // pitch)
    sites = [(i * pitch, -length / 2 + 1.15 * radius + j * pitch, k * pitch)
             for i in range(-span, span + 1) for k in range(-span, span + 1)
             for j in range(int((length - 2.3 * radius) // pitch) + 1) if (i * pitch) ** 2 + (k * pitch) ** 2 < (inner - radius) ** 2]
    if len(sites) < n:
        raise ValueError('drum: only %d of n=%d spheres fit in the drum (drumRadius=%g m, length=%g m); allowed: a '
                         'larger drum or fewer spheres (fill)' % (len(sites), n, drumRadius, length))
    sites.sort(key=lambda c: (c[2], c[0], c[1]))
    jitter = 0.04 * radius
    return [O.bodies.append(utils.sphere(tuple(x + rng.uniform(-jitter, jitter) for x in c), radius * rng.uniform(0.9, 1.0),
                                         material=material)) for c in sites[:n]]
