"""The liquid of a wet scene with conserved liquid (``liquidModel='film'``, docs/physics.md §11).

Each particle carries a film (:yref:`ViscBridgeState.film`, m³); a bridge forms only where the two
particles carry liquid, takes its volume from their films and gives it back when it ruptures
(the engine :yref:`ViscBridgeLiquid`).  This module sets and reads that liquid::

    import viscbridge, viscbridge.liquid as liquid
    O.engines = viscbridge.engines(viscosity=10, liquidModel='film', bridgeVolumeRel=0.02)
    liquid.set_film(spheres, 0.01 * particle_volume)   # before or between runs
    O.engines += [liquid.spray(rate=1e-9, box=((0, 0, 0.01), (0.02, 0.02, 0.02)), end=0.5)]
    O.run(10000, True)
    liquid.total(), liquid.distribution().cov

Every function reads ``O`` when it is called; none needs the film model to read a scene (with
'fixed' bridges, ``total()`` counts their volumes too).
"""
import math

from . import _checks

__all__ = ['set_film', 'add', 'film', 'total', 'in_films', 'in_bridge', 'in_bridges', 'distribution', 'Distribution',
           'spray', 'Spray', 'make_dry', 'sprayed']


def _ids(func, ids, spheres_only=True):
    """`ids` as a list of ids of existing bodies of O.bodies — spheres only, unless told otherwise
    (ValueError naming a bad one)."""
    from yade import O
    import yade.wrapper as yw
    if isinstance(ids, int) and not isinstance(ids, bool):
        ids = [ids]
    try:
        ids = list(ids)
    except TypeError:
        _checks.reject(func, 'ids', ids, 'a body id or a list of body ids')
    for i in ids:
        if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < len(O.bodies) or O.bodies[i] is None:
            _checks.reject(func, 'ids', i, 'ids of existing bodies (0 to %d)' % (len(O.bodies) - 1))
        if spheres_only and not isinstance(O.bodies[i].shape, yw.Sphere):
            _checks.reject(func, 'ids', i, 'spheres only (body %d is a %s: walls and facets carry no film)'
                           % (i, type(O.bodies[i].shape).__name__))
    return ids


def _volumes(func, ids, volume):
    """One non-negative finite volume per id: `volume` is a number or a sequence as long as `ids`."""
    if isinstance(volume, (int, float)) and not isinstance(volume, bool):
        volume = [volume] * len(ids)
    volume = list(volume)
    if len(volume) != len(ids):
        _checks.reject(func, 'volume', '%d values' % len(volume), 'one volume or one per id (%d)' % len(ids))
    return [_checks.non_negative(func, 'volume', v, ' [m³]') for v in volume]


def set_film(ids, volume):
    """Set the film of the spheres `ids` (an id or a list) to `volume` [m³] (one value, or one per id)."""
    import yade.wrapper as yw
    from yade import O
    ids = _ids('set_film', ids)
    for i, v in zip(ids, _volumes('set_film', ids, volume)):
        yw.ViscBridgeState.of(O.bodies[i]).film = v


def add(ids, volume):
    """Add `volume` [m³] (one value, or one per id) to the films of the spheres `ids`: binder added
    during a run (between ``O.run`` calls or from a PyRunner)."""
    import yade.wrapper as yw
    from yade import O
    ids = _ids('add', ids)
    for i, v in zip(ids, _volumes('add', ids, volume)):
        state = yw.ViscBridgeState.of(O.bodies[i])
        state.film = state.film + v


def film(id):
    """The film of body `id` [m³] (0 for a body that never had one)."""
    from yade import O
    _ids('film', [id])
    return getattr(O.bodies[id].state, 'film', 0.0)


def in_films():
    """The liquid in all films [m³]."""
    from yade import O
    return math.fsum(getattr(b.state, 'film', 0.0) for b in O.bodies if b is not None)


def _bridges():
    from yade import O
    import yade.wrapper as yw
    return [i for i in O.interactions if i.isReal and isinstance(i.phys, yw.ViscBridgePhys) and i.phys.bridge]


def in_bridge(phys):
    """The liquid a ViscBridge contact (its ViscBridgePhys `phys`) holds [m³]: its bridge's volume, 0
    without a bridge.  A contact without a bridge keeps in ``bridgeVolume`` the largest volume a
    bridge forming there may take (the Ip2's): that is no liquid, and summing it over contacts counts
    liquid that is not there."""
    return phys.bridgeVolume if phys.bridge else 0.0


def in_bridges():
    """The liquid in all existing bridges [m³]."""
    return math.fsum(in_bridge(i.phys) for i in _bridges())


def total():
    """All the liquid of the scene, films + bridges [m³].  With liquidModel='film' it changes only by
    what :func:`add`, :func:`set_film` and :func:`spray` put in (and by erasing bodies)."""
    return in_films() + in_bridges()


class Distribution:
    """Per-particle liquid: ``ids`` (the spheres), ``liquid`` [m³] (film + its share of each bridge:
    half, all of a bridge to a wall or facet), ``mean`` and ``cov`` (standard deviation / mean, the
    uniformity measure granulation studies report; 0 for a uniform liquid, nan without liquid)."""

    def __init__(self, ids, liquid):
        import numpy
        self.ids, self.liquid = numpy.asarray(ids, dtype=int), numpy.asarray(liquid, dtype=float)
        self.mean = float(self.liquid.mean()) if len(self.liquid) else math.nan
        self.cov = float(self.liquid.std() / self.mean) if self.mean > 0 else math.nan

    def __repr__(self):
        return 'Distribution(%d spheres, mean %.4g m³, CoV %.3g)' % (len(self.ids), self.mean, self.cov)


def distribution():
    """The liquid per sphere as a :class:`Distribution`."""
    from yade import O
    import yade.wrapper as yw
    spheres = [b.id for b in O.bodies if b is not None and isinstance(b.shape, yw.Sphere)]
    where = {i: k for k, i in enumerate(spheres)}
    liquid = [getattr(O.bodies[i].state, 'film', 0.0) for i in spheres]
    for I in _bridges():
        ends = [i for i in (I.id1, I.id2) if i in where]
        for i in ends:
            liquid[where[i]] += in_bridge(I.phys) / len(ends)
    return Distribution(spheres, liquid)


class Spray:
    """Binder sprayed at `rate` [m³/s] from `start` to `end` [s of simulated time] onto the spheres
    whose centre is in the zone (a box or a ball), shared in proportion to their cross-sections
    (r²).  Called by its PyRunner; ``delivered`` is what it has put into films [m³], ``pending``
    what it holds while no sphere is in the zone (given to the next ones that are)."""

    def __init__(self, rate, box, ball, start, end):
        self.rate, self.box, self.ball, self.start, self.end = rate, box, ball, start, end
        self.last, self.delivered, self.pending = None, 0.0, 0.0

    def inside(self, pos):
        if self.box is not None:
            return all(self.box[0][k] <= pos[k] <= self.box[1][k] for k in range(3))
        centre, radius = self.ball
        return sum((pos[k] - centre[k]) ** 2 for k in range(3)) <= radius * radius

    def __call__(self):
        from yade import O
        import yade.wrapper as yw
        now = O.time + O.dt  # runs after the integrator: the end of this step
        last = self.start if self.last is None else self.last
        self.pending += self.rate * max(0.0, min(now, self.end) - max(last, self.start))
        self.last = now
        targets = [b for b in O.bodies if b is not None and isinstance(b.shape, yw.Sphere) and self.inside(b.state.pos)]
        if not targets or self.pending <= 0:
            return
        weights = [b.shape.radius ** 2 for b in targets]
        scale = self.pending / math.fsum(weights)
        add([b.id for b in targets], [w * scale for w in weights])
        self.delivered += self.pending
        self.pending = 0.0


_SPRAYS = []


def spray(rate, box=None, ball=None, start=0.0, end=math.inf, iterPeriod=100):
    """A PyRunner that sprays binder at `rate` [m³/s] onto the spheres in a zone — ``box=((xmin, ymin,
    zmin), (xmax, ymax, zmax))`` or ``ball=((x, y, z), radius)`` — between the simulated times
    `start` and `end` [s], every `iterPeriod` steps; append it to O.engines.  Its :class:`Spray` is
    ``viscbridge.liquid.sprays()[-1]`` (``delivered``, ``pending``)."""
    import yade.wrapper as yw
    f = 'spray'
    rate = _checks.positive(f, 'rate', rate, ' [m³/s]')
    if (box is None) == (ball is None):
        raise ValueError('spray: give exactly one zone, box=((xmin, ymin, zmin), (xmax, ymax, zmax)) or ball=((x, y, z), radius)')
    if box is not None:
        try:
            box = tuple(tuple(_checks.number(f, 'box', c, 'two corners of three finite numbers [m]') for c in corner) for corner in box)
        except TypeError:
            box = None
        if box is None or len(box) != 2 or any(len(c) != 3 for c in box) or any(box[0][k] > box[1][k] for k in range(3)):
            _checks.reject(f, 'box', box, '((xmin, ymin, zmin), (xmax, ymax, zmax)) with min <= max [m]')
    else:
        try:
            centre, radius = ball
            centre = tuple(_checks.number(f, 'ball', c, 'a centre of three finite numbers [m]') for c in centre)
        except (TypeError, ValueError):
            centre = None
        if centre is None or len(centre) != 3:
            _checks.reject(f, 'ball', ball, '((x, y, z), radius) [m]')
        ball = (centre, _checks.positive(f, 'ball radius', radius, ' [m]'))
    start = _checks.non_negative(f, 'start', start, ' [s]')
    if not (isinstance(end, (int, float)) and end > start):
        _checks.reject(f, 'end', end, 'a time after start=%g [s] (inf: no end)' % start)
    _SPRAYS.append(Spray(rate, box, ball, start, float(end)))
    return yw.PyRunner(iterPeriod=_checks.integer(f, 'iterPeriod', iterPeriod, minimum=1),
                       command='import viscbridge.liquid; viscbridge.liquid._SPRAYS[%d]()' % (len(_SPRAYS) - 1))


def sprays():
    """The :class:`Spray` objects of this session, in the order :func:`spray` made them."""
    return list(_SPRAYS)


def make_dry(ids=None, material=None):
    """Make bodies dry: no liquid bridge forms on them (any liquid model) — e.g. a drum wall that
    does not wet.  Give body ids, or a material (every body made of it).  Applies to interactions
    created from now on: call it before the run."""
    import yade.wrapper as yw
    from yade import O
    if (ids is None) == (material is None):
        raise ValueError('make_dry: give exactly one of ids=[...] or material=...')
    if material is not None:
        if not isinstance(material, yw.Material) or material.id < 0:
            _checks.reject('make_dry', 'material', material, 'a Material of O.materials')
        ids = [b.id for b in O.bodies if b is not None and b.material.id == material.id]
    else:
        ids = _ids('make_dry', ids, spheres_only=False)
    for i in ids:
        yw.ViscBridgeState.of(O.bodies[i]).wettable = False
    return ids


def sprayed():
    """The liquid that sprays have put into the films so far [m³]."""
    return math.fsum(s.delivered for s in _SPRAYS)
