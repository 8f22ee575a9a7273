"""The liquid of a wet scene with conserved liquid (``liquidModel='film'``, docs/physics.md §11).

Each particle carries a film (:yref:`ViscBridgeState.film`, m³); a bridge forms only where the two
particles carry liquid, takes its volume from their films and gives it back when it ruptures
(the engine :yref:`ViscBridgeLiquid`).  This module sets and reads that liquid::

    import viscbridge, viscbridge.liquid as liquid
    O.engines = viscbridge.engines(viscosity=10, liquidModel='film', bridgeVolumeRel=0.02)
    liquid.set_film(spheres, 0.01 * particle_volume)   # before or between runs
    O.engines += [liquid.spray(rate=1e-9, box=((0, 0, 0), (0.02, 0.02, 0.02)), end=0.5)]  # onto the bed's top
    O.run(10000, True)
    liquid.total(), liquid.distribution().cov

Every function reads ``O`` when it is called; none needs the film model to read a scene (with
'fixed' bridges, ``total()`` counts their volumes too).
"""
import math

from . import _checks

__all__ = ['set_film', 'add', 'film', 'total', 'in_films', 'in_bridge', 'in_bridges', 'distribution', 'Distribution',
           'spray', 'sprays', 'sprayed', 'make_dry']


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


def _refuse_split(func):
    """RuntimeError while yade.mpy has the scene split: a film set on one rank's copy of a body would
    not reach its owner or its mirrors on the other ranks."""
    from . import mpi
    if mpi.is_split():
        raise RuntimeError('viscbridge.liquid.%s: the scene is split over the %d ranks of yade.mpy, where each rank owns only '
                           'its own bodies\' films; set films before the first mp.mpirun (every rank runs the script), or '
                           'add binder serially (a spray does not run under yade.mpy)' % (func, mpi.ranks()))


def set_film(ids, volume):
    """Set the film of the spheres `ids` (an id or a list) to `volume` [m³] (one value, or one per id)."""
    import yade.wrapper as yw
    from yade import O
    _refuse_split('set_film')
    ids = _ids('set_film', ids)
    for i, v in zip(ids, _volumes('set_film', ids, volume)):
        yw.ViscBridgeState.of(O.bodies[i]).film = v
        _warn_if_beyond_sphere('set_film', i, v)


def add(ids, volume):
    """Add `volume` [m³] (one value, or one per id) to the films of the spheres `ids`: binder added
    during a run (between ``O.run`` calls or from a PyRunner)."""
    import yade.wrapper as yw
    from yade import O
    _refuse_split('add')
    ids = _ids('add', ids)
    for i, v in zip(ids, _volumes('add', ids, volume)):
        state = yw.ViscBridgeState.of(O.bodies[i])
        state.film = state.film + v
        _warn_if_beyond_sphere('add', i, state.film)


def _warn_if_beyond_sphere(func, i, film):
    """A film larger than its sphere is legal but almost surely a unit slip (a fraction typed as m³)."""
    from yade import O
    own = 4 / 3 * math.pi * O.bodies[i].shape.radius ** 3
    if film > own:
        _checks.implausible('film', '%s: body #%d gets a film of %.4g m³, more than its own volume (%.4g m³): films are in m³ '
                                    '(for a fraction of the sphere\'s volume multiply by it)' % (func, i, film, own))


def film(id):
    """The film of body `id` [m³] (0 for a body that never had one)."""
    from yade import O
    _ids('film', [id])
    return getattr(O.bodies[id].state, 'film', 0.0)


def _over_ranks(mine, me):
    """The sum of `mine` over the ranks (a collective while split), `mine` otherwise."""
    from . import mpi
    return mine if me is None else math.fsum(mpi.allgather(mine))


def in_films():
    """The liquid in all films [m³].  While yade.mpy has the scene split, a collective (call it on every
    rank): the whole scene's, on every rank."""
    from yade import O
    from . import mpi
    me = mpi.split_rank()
    return _over_ranks(math.fsum(getattr(b.state, 'film', 0.0) for b in O.bodies if b is not None and mpi.accounts_for_body(b, me)), me)


def _bridges():
    """The bridges of the interactions this rank holds."""
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
    """The liquid in all existing bridges [m³] (a collective while yade.mpy has the scene split, as
    :func:`in_films`)."""
    from . import mpi
    me = mpi.split_rank()
    return _over_ranks(math.fsum(in_bridge(I.phys) for I in _bridges() if mpi.accounts_for_pair(I.id1, I.id2, me)), me)


def total():
    """All the liquid of the scene, films + bridges [m³].  With liquidModel='film' it changes only by
    what :func:`add`, :func:`set_film` and :func:`spray` put in (and by erasing bodies).  A collective
    while yade.mpy has the scene split (as :func:`in_films`)."""
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
    """The liquid per sphere as a :class:`Distribution`.  While yade.mpy has the scene split, a
    collective (call it on every rank): every rank gets the whole scene's, by sphere id as serially."""
    from yade import O
    import yade.wrapper as yw
    from . import mpi
    me = mpi.split_rank()
    sphere = lambda i: O.bodies[i] is not None and isinstance(O.bodies[i].shape, yw.Sphere)
    spheres = [b.id for b in O.bodies if b is not None and isinstance(b.shape, yw.Sphere) and mpi.accounts_for_body(b, me)]
    where = {i: k for k, i in enumerate(spheres)}
    liquid = [getattr(O.bodies[i].state, 'film', 0.0) for i in spheres]
    for I in _bridges():
        ends = [i for i in (I.id1, I.id2) if sphere(i)]  # under mpy one may be a neighbour's mirror
        for i in ends:
            if i in where:
                liquid[where[i]] += in_bridge(I.phys) / len(ends)
    if me is not None:
        joined = sorted(p for part in mpi.allgather(list(zip(spheres, liquid))) for p in part)
        spheres, liquid = [i for i, _ in joined], [v for _, v in joined]
    return Distribution(spheres, liquid)


def spray(rate, box=None, ball=None, start=None, end=math.inf, nozzle=(0, 0, -1), maxFilmRel=0.1, dropletVolume=0.0,
          seed=0, iterPeriod=100, virtPeriod=None, label=''):
    """A :yref:`ViscBridgeSpray` engine that sprays binder at `rate` [m³/s] between the simulated times
    `start` (default: now, O.time; not before it, or the binder of the time past would land at
    once) and `end` [s] onto the spheres in a zone — ``box=((xmin, ymin, zmin), (xmax, ymax, zmax))``
    or ``ball=((x, y, z), radius)`` [m] — that the spray reaches (physics.md L6, L7): droplets travel
    along `nozzle` (default straight down, −z; ``None``: every sphere in the zone, hidden or not) and
    wet the first sphere they meet, so the bed's free surface in the zone takes the liquid, in
    proportion to the area each sphere shows the nozzle, recomputed as the bed moves.  No film grows
    beyond `maxFilmRel` × its sphere's volume; the excess goes to the other reached spheres, and waits
    (``pending``) when all are full.  `dropletVolume` [m³]: 0, a fine mist shared over every reached
    sphere at each call; above 0, whole droplets, each landing on one reached sphere drawn by the area
    it shows the nozzle (L6b; `seed` fixes the draws).  Every `iterPeriod` steps (or `virtPeriod` [s]).  Append it to
    O.engines (after the NewtonIntegrator); it is saved with the scene and continues after O.load,
    nothing sprayed twice.  ``sprayed``, ``delivered`` and ``pending`` [m³] are its attributes;
    YADE's log warns once when the liquid waits because no sphere is reached, all are full, or the
    window has ended."""
    import yade.wrapper as yw
    f = 'spray'
    rate = _checks.non_negative(f, 'rate', rate, ' [m³/s]')
    if (box is None) == (ball is None):
        raise ValueError('spray: give exactly one zone, box=((xmin, ymin, zmin), (xmax, ymax, zmax)) or ball=((x, y, z), radius) [m]')
    zone = _box_zone(f, box) if box is not None else _ball_zone(f, ball)
    start = _spray_start(f, 'start', start, 1.0, ' [s]')
    if not (isinstance(end, (int, float)) and not isinstance(end, bool) and end > start):
        _checks.reject(f, 'end', end, 'a time after start=%g [s] (inf: no end)' % start)
    direction = (0.0, 0.0, 0.0) if nozzle is None else _vector(f, 'nozzle', nozzle, 'a direction (x, y, z), not zero; None: no shadow')
    if nozzle is not None and not any(direction):
        _checks.reject(f, 'nozzle', nozzle, 'a direction (x, y, z), not zero; None: no shadow')
    engine = yw.ViscBridgeSpray(rate=rate, start=start, end=-1.0 if math.isinf(end) else float(end), nozzle=direction,
                                maxFilmRel=_checks.positive(f, 'maxFilmRel', maxFilmRel),
                                dropletVolume=_checks.non_negative(f, 'dropletVolume', dropletVolume, ' [m³]'),
                                seed=_checks.integer(f, 'seed', seed, minimum=0), label=label, **zone)
    if virtPeriod is not None:
        engine.virtPeriod = _checks.positive(f, 'virtPeriod', virtPeriod, ' [s]')
    else:
        engine.iterPeriod = _checks.integer(f, 'iterPeriod', iterPeriod, minimum=1)
    return engine


def _spray_start(func, name, start, unit, text):
    """The start time [s] of a spray asked for at `start` × `unit` seconds (None: now): not before
    O.time, whose binder would otherwise land all at once (a start within rounding of now is now)."""
    from yade import O
    if start is None:
        return O.time
    start = _checks.non_negative(func, name, start, text) * unit
    if start < O.time * (1 - 1e-12):
        _checks.reject(func, name, start / unit, '>= %.6g%s, now (O.time = %.6g s; None, the default: now): the binder of '
                       'the time already past would land at once' % (O.time / unit, text, O.time))
    return max(start, O.time)


def _vector(func, name, value, allowed):
    try:
        v = tuple(_checks.number(func, name, c, allowed) for c in value)
    except TypeError:
        v = ()
    if len(v) != 3:
        _checks.reject(func, name, value, allowed)
    return v


def _box_zone(func, box):
    try:
        corners = [_vector(func, 'box', c, 'two corners of three finite numbers [m]') for c in box]
    except (TypeError, ValueError):
        corners = []
    if len(corners) != 2 or any(corners[0][k] > corners[1][k] for k in range(3)):
        _checks.reject(func, 'box', box, '((xmin, ymin, zmin), (xmax, ymax, zmax)) with min <= max [m]')
    return dict(boxMin=corners[0], boxMax=corners[1])


def _ball_zone(func, ball):
    try:
        centre, radius = ball
    except (TypeError, ValueError):
        _checks.reject(func, 'ball', ball, '((x, y, z), radius) [m]')
    centre = _vector(func, 'ball', centre, 'a centre of three finite numbers [m]')
    return dict(ballCentre=centre, ballRadius=_checks.positive(func, 'ball radius', radius, ' [m]'))


def sprays():
    """The :yref:`ViscBridgeSpray` engines of O.engines, in their order there."""
    from yade import O
    import yade.wrapper as yw
    return [e for e in O.engines if isinstance(e, yw.ViscBridgeSpray)]


def sprayed():
    """The liquid the sprays of O.engines have put into the films so far [m³] (their ``delivered``)."""
    return math.fsum(s.delivered for s in sprays())


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
