"""Agglomerates: the connected components of the graph of liquid bridges between dynamic spheres.

Every dynamic sphere belongs to exactly one agglomerate (a lone sphere is one of size 1; a clump of
spheres counts as one particle); walls, facets and fixed bodies are not members and do not join two
agglomerates.  What granulation studies
report is computed from them: the size distribution, the largest agglomerate, the mean coordination
number (bridges to other spheres per sphere), mass fractions and, with conserved liquid
(liquidModel='film'), the liquid per agglomerate and the CoV of the liquid per particle.

:func:`components` is the pure part (numpy, scipy's connected components: linear in the number of
bridges); :func:`agglomerates` reads it off O.
"""
import math

import numpy

__all__ = ['Agglomerates', 'components', 'agglomerates', 'edges_of_scene', 'transitions']


class Agglomerates:
    """The agglomerates of a scene (see the module).  Attributes:

    ``ids`` the member spheres' body ids; ``labels`` their agglomerate (0 = largest; ties by the
    smallest body id), ``sizes`` spheres per agglomerate, descending; ``largest`` ``sizes[0]``;
    ``count`` the number of agglomerates; ``coordination`` bridges between members per member
    (each counted at both ends); ``masses`` and ``mass_fractions`` per agglomerate; ``liquid`` per
    agglomerate [m³] (films + bridges, each bridge's liquid in the agglomerate it joins) and
    ``liquid_cov`` — both None without per-particle liquid.
    """

    def __init__(self, ids, labels, edges, masses, liquid=None):
        self.ids, self.labels = ids, labels
        self.count = int(labels.max()) + 1 if len(labels) else 0
        self.sizes = numpy.bincount(labels, minlength=self.count)
        self.largest = int(self.sizes[0]) if self.count else 0
        self.coordination = 2.0 * len(edges) / len(ids) if len(ids) else math.nan
        self.masses = numpy.bincount(labels, weights=masses, minlength=self.count)
        self.mass_fractions = self.masses / self.masses.sum() if self.count else self.masses
        self.liquid = self.liquid_cov = None
        if liquid is not None:
            per_particle = liquid
            self.liquid = numpy.bincount(labels, weights=per_particle, minlength=self.count)
            mean = per_particle.mean() if len(per_particle) else math.nan
            self.liquid_cov = float(per_particle.std() / mean) if mean > 0 else math.nan

    def label_of(self, body_id):
        """The agglomerate of body `body_id` (0 = largest); KeyError for a body that is not a member."""
        where = numpy.searchsorted(self.ids, body_id)
        if where >= len(self.ids) or self.ids[where] != body_id:
            raise KeyError('body %r is not a member of any agglomerate (only dynamic spheres are)' % (body_id,))
        return int(self.labels[where])

    def size_distribution(self, bins=None, by='number'):
        """Histogram of agglomerate sizes (spheres per agglomerate): (counts, edges).  `bins` as numpy's
        (default: 1, 2, 3–4, 5–8, ... doubling); by='number' counts agglomerates, by='mass' sums their
        mass fractions."""
        if by not in ('number', 'mass'):
            raise ValueError("size_distribution: by=%r; allowed: 'number', 'mass'" % (by,))
        if bins is None:
            top = max(1, self.largest)
            bins = [1] + [2 ** k + 0.5 for k in range(0, int(math.ceil(math.log2(top))) + 1)]
            bins[-1] = max(bins[-1], top + 0.5)
        weights = self.mass_fractions if by == 'mass' else None
        return numpy.histogram(self.sizes, bins=bins, weights=weights)

    def __repr__(self):
        return 'Agglomerates(%d spheres in %d agglomerates, largest %d, coordination %.2f)' % (
            len(self.ids), self.count, self.largest, self.coordination)


def components(ids, edges, masses, liquid=None):
    """Agglomerates of the spheres `ids` (sorted body ids) joined by `edges` (pairs of body ids, both
    members); `masses` per member; `liquid` optional (per-particle liquid, per-edge liquid)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    ids = numpy.asarray(ids, dtype=numpy.int64)
    edges = numpy.asarray(edges, dtype=numpy.int64).reshape(-1, 2)
    n = len(ids)
    a, b = numpy.searchsorted(ids, edges[:, 0]), numpy.searchsorted(ids, edges[:, 1])
    graph = coo_matrix((numpy.ones(len(edges)), (a, b)), shape=(n, n))
    _, raw = connected_components(graph, directed=False)
    # relabel: 0 = largest, ties by the smallest member id (ids are sorted: first index = smallest id)
    sizes = numpy.bincount(raw)
    first = numpy.full(len(sizes), n)
    numpy.minimum.at(first, raw, numpy.arange(n))
    order = numpy.lexsort((first, -sizes))
    rank = numpy.empty_like(order)
    rank[order] = numpy.arange(len(order))
    labels = rank[raw]
    liquid = None if liquid is None else numpy.asarray(liquid, dtype=float)
    return Agglomerates(ids, labels, edges, numpy.asarray(masses, dtype=float), liquid)


def transitions(previous, current):
    """(broken, merged) between two :class:`Agglomerates` of the same run: ``broken`` counts the
    agglomerates of `previous` whose members now lie in more than one agglomerate (breakage or
    erosion), ``merged`` the agglomerates of `current` made of members of more than one previous
    agglomerate (coalescence or layering).  Only spheres present at both times count; an agglomerate
    may have both broken and merged in between, as granules do in a flow."""
    common, at_prev, at_cur = numpy.intersect1d(previous.ids, current.ids, assume_unique=True, return_indices=True)
    if not len(common):
        return 0, 0
    pairs = numpy.unique(numpy.stack([previous.labels[at_prev], current.labels[at_cur]], axis=1), axis=0)
    broken = numpy.count_nonzero(numpy.bincount(pairs[:, 0]) > 1)
    merged = numpy.count_nonzero(numpy.bincount(pairs[:, 1]) > 1)
    return int(broken), int(merged)


def _node(body):
    """The member a body stands for: a dynamic sphere itself, a clump's sphere its clump (a clump
    is one particle); None for anything else."""
    import yade.wrapper as yw
    if body is None or not isinstance(body.shape, yw.Sphere):
        return None
    if body.isClumpMember:
        return body.clumpId
    return body.id if body.dynamic else None


def edges_of_scene(min_force=0.0, min_volume=0.0):
    """(member ids, edges, masses, per-member liquid or None) read off O: members are the dynamic
    spheres and the clumps of spheres, edges the liquid bridges between two members carrying at
    least `min_force` [N] (the magnitude of the interaction's total force) and holding at least
    `min_volume` [m³].  While yade.mpy has the scene split, those of the whole scene, gathered from
    every rank (a collective: call it on every rank)."""
    from yade import O
    from .. import mpi
    node = {b.id: _node(b) for b in O.bodies if b is not None}
    if mpi.is_split():
        return _edges_over_ranks(node, min_force, min_volume)
    members = sorted({m for m in node.values() if m is not None})
    with_liquid = any(hasattr(O.bodies[i].state, 'film') for i, m in node.items() if m is not None)
    edges = _bridges(O.interactions, node, min_force, min_volume)
    masses = [O.bodies[m].state.mass for m in members]
    return members, edges, masses, _liquid_of(members, node.get) if with_liquid else None


def _liquid_of(members, member_of):
    """Each member's liquid: its spheres' (film + share of each bridge, viscbridge.liquid's one rule;
    a collective while yade.mpy has the scene split), a sphere's member given by `member_of(id)`
    (None: not a member)."""
    from .. import liquid
    index = {m: k for k, m in enumerate(members)}
    per_member = numpy.zeros(len(members))
    spread = liquid.distribution()
    for i, volume in zip(spread.ids.tolist(), spread.liquid.tolist()):
        if member_of(i) in index:
            per_member[index[member_of(i)]] += volume
    return per_member


def _bridges(interactions, node, min_force, min_volume):
    """The (member, member) pairs of the liquid bridges among `interactions` that carry at least
    `min_force` and hold at least `min_volume`."""
    import yade.wrapper as yw
    edges = []
    for I in interactions:
        if not (I.isReal and isinstance(I.phys, yw.ViscBridgePhys) and I.phys.bridge):
            continue
        ends = [node.get(i) for i in (I.id1, I.id2)]
        if None not in ends and ends[0] != ends[1] and I.phys.bridgeVolume >= min_volume and (
                min_force <= 0 or (I.phys.normalForce + I.phys.shearForce).norm() >= min_force):
            edges.append(tuple(ends))
    return edges


def _edges_over_ranks(node, min_force, min_volume):
    """edges_of_scene of a scene yade.mpy has split: each rank gives the members it owns and the
    bridges that touch one (a bridge between two workers' spheres is computed on both, with the same
    values, and counted once; the master's copies of the workers' spheres are stale and give
    nothing), every rank joins the parts; the liquid per member from the collective
    viscbridge.liquid.distribution()."""
    from yade import O
    from .. import mpi
    me = mpi.split_rank()
    own = {b.id for b in O.bodies if b is not None and mpi.accounts_for_body(b, me)}
    members = [(m, O.bodies[m].state.mass) for m in sorted(own) if node.get(m) == m]
    touching = [I for I in O.interactions if I.isReal and (I.id1 in own or I.id2 in own)]
    with_liquid = any(hasattr(O.bodies[m].state, 'film') for m in own if node.get(m) is not None)
    parts = mpi.allgather((members, _bridges(touching, node, min_force, min_volume), with_liquid))
    members = sorted(m for part, _, _ in parts for m in part)
    edges = sorted({tuple(sorted(e)) for _, part, _ in parts for e in part})
    ids = [m for m, _ in members]
    # every rank takes the same branch (the collective distribution); no clumps under mpy: a sphere is its member
    per_member = _liquid_of(ids, lambda i: i) if any(wet for _, _, wet in parts) else None
    return ids, edges, [mass for _, mass in members], per_member


def agglomerates(scene=None, min_force=0.0, min_volume=0.0):
    """The :class:`Agglomerates` of O — or of the saved scene `scene` (a file name, loaded into O with
    O.load).  An edge is a liquid bridge between two dynamic spheres; with `min_force` [N] only
    bridges that carry at least that force (a bridge that carries no load in a dense flow does not
    make a granule), with `min_volume` [m³] only bridges that hold at least that liquid.  While
    yade.mpy has the scene split, a collective: call it on every rank; each gets the whole scene's."""
    from .. import _checks
    f = 'agglomerates'
    min_force = _checks.non_negative(f, 'min_force', min_force, ' [N]')
    min_volume = _checks.non_negative(f, 'min_volume', min_volume, ' [m³]')
    if scene is not None:
        from yade import O
        import os
        if not isinstance(scene, str) or not os.path.isfile(scene):
            _checks.reject(f, 'scene', scene, 'the file name of a saved scene (O.save)')
        O.load(scene)
    members, edges, masses, per_particle = edges_of_scene(min_force, min_volume)
    return components(members, edges, masses, per_particle)
