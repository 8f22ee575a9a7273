"""One large ViscBridge scene over several MPI processes, with YADE's own ``yade.mpy``.

A script like this, started on N ranks (``./yadew mpirun -n N my_scene.py``, or ``mpiexec -n N yade
-n -x my_scene.py`` on a cluster), runs the scene split into N−1 subdomains::

    from yade import mpy as mp
    import viscbridge.scenes as scenes
    import viscbridge.mpi

    s = scenes.settling(n=20000, viscosity=1.0)  # every rank builds it; mpy distributes rank 0's copy
    viscbridge.mpi.decompose()                    # which worker owns which particle
    mp.mpirun(2000, withMerge=True)               # rank 0 then holds the whole scene again
    E = viscbridge.mpi.energy()                   # O.energy summed over the ranks (on every rank)
    if viscbridge.mpi.rank() == 0:
        O.save('settled.yade.gz')                 # the merged scene; viscbridge.mpi.to_serial() after
                                                  # O.load() runs it on in one process

The engines of :func:`viscbridge.engines` need nothing else: the time stepper takes the smallest
bound over the ranks, so every rank steps with the same dt; the guard checks the energy of the whole
scene and names the rank and the body when it stops a run; the implicit solver solves one system
over all ranks.  Rank 0 (mpy's master) keeps the walls and other bodies left in subdomain 0; it
should own no moving particle (mpy never sends their states to the workers).
"""
import os
import sys

__all__ = ['ranks', 'rank', 'decompose', 'absolute_verlet_distance', 'energy', 'energy_total', 'to_serial', 'split_rank', 'accounts_for_body', 'accounts_for_pair',
           'is_split', 'allgather', 'move_boundaries_on_workers']


def _launched_by_mpiexec():
    return any(v in os.environ for v in ('OMPI_COMM_WORLD_SIZE', 'PMI_SIZE', 'PMIX_RANK'))


def _mpy():
    """yade.mpy if this process is one of several MPI ranks, else None (a serial run: nothing to do).
    Under mpiexec it is imported here if the script has not done it yet, so that the answer does
    not depend on the order of the imports."""
    mp = sys.modules.get('yade.mpy')
    if mp is None and _launched_by_mpiexec():
        from yade import mpy as mp
    if mp is None or not mp.numThreads or mp.numThreads < 2:
        return None
    return mp


def ranks():
    """Number of MPI ranks of this run (1 when serial)."""
    mp = _mpy()
    return mp.numThreads if mp else 1


def rank():
    """This process's rank (0 when serial; 0 is mpy's master)."""
    mp = _mpy()
    return mp.rank if mp else 0


def is_split():
    """Whether this rank holds only its share of a scene split by yade.mpy (between ``mp.mpirun``
    without merging and ``mp.mergeScene``)."""
    from yade import O
    return bool(getattr(O, 'splitted', False)) and ranks() > 1


def allgather(value):
    """Every rank's `value`, in rank order, on every rank (a collective under mpy: call it on every
    rank at the same point); ``[value]`` serially."""
    mp = _mpy()
    return mp.comm.allgather(value) if mp else [value]


def split_rank():
    """This rank while yade.mpy has the scene split, None otherwise.  While split, a rank accounts for
    the bodies it owns (:func:`accounts_for_body`) and for an interaction between two ranks' bodies
    on the higher rank (:func:`accounts_for_pair`), so that sums over the ranks count each once (as
    ViscBridge's engines do, distributed::Ownership)."""
    return rank() if is_split() else None


def accounts_for_body(body, me):
    """Whether the rank `me` (:func:`split_rank`; None: not split) accounts for `body`."""
    return me is None or body.subdomain == me


def accounts_for_pair(id1, id2, me):
    """Whether the rank `me` (:func:`split_rank`; None: not split) accounts for the interaction of
    bodies `id1` and `id2` (both held here)."""
    from yade import O
    return me is None or max(O.bodies[id1].subdomain, O.bodies[id2].subdomain) == me


def absolute_verlet_distance():
    """Turn a relative ``InsertionSortCollider.verletDist`` (< 0: a fraction of the smallest sphere
    radius, the default) into the absolute distance it stands for, on every collider of O.engines.
    Under mpy the master holds no spheres: its collider would take a verletDist of 0 and so ask for a
    collision detection at every step, on every rank.  Serially this changes nothing (the collider
    computes the same value at its first run).  Returns the distances set [m]."""
    from yade import O
    import yade.wrapper as yw
    radii = [b.shape.radius for b in O.bodies if b and isinstance(b.shape, yw.Sphere)]
    out = []
    for e in O.engines:
        if isinstance(e, yw.InsertionSortCollider) and e.verletDist < 0 and radii:
            e.verletDist = abs(e.verletDist) * min(radii)
            out.append(e.verletDist)
    return out


def decompose(axis=None, workers=None):
    """Assign every free sphere to one of the workers (``Body.subdomain`` 1…workers, default
    ranks−1) in slabs of equal numbers of spheres along `axis` (0, 1 or 2; default: the longest
    extent of the spheres); every other body (walls, facets, fixed bodies) stays with the master
    (subdomain 0).  Call it on every rank before ``mp.mpirun``, after the scene is built.  Returns
    the number of spheres per worker.  It also fixes the colliders' verletDist
    (:func:`absolute_verlet_distance`) and puts a ViscBridgeBoundaryMotion after NewtonIntegrator
    (:func:`move_boundaries_on_workers`).  Serially (one rank) it does nothing and returns []."""
    from yade import O
    import yade.wrapper as yw
    if workers is None:
        workers = ranks() - 1
    if not isinstance(workers, int) or isinstance(workers, bool) or workers < 0:
        raise ValueError('decompose(workers=%r): allowed: an integer >= 1 (the ranks other than the master)' % (workers,))
    if axis is not None and (isinstance(axis, bool) or axis not in (0, 1, 2)):
        raise ValueError('decompose(axis=%r): allowed: 0, 1, 2 or None (the longest extent)' % (axis,))
    if workers == 0:
        return []
    spheres = [b for b in O.bodies if b and isinstance(b.shape, yw.Sphere) and b.dynamic and not b.isClumpMember]
    if not spheres:
        raise ValueError('decompose(): the scene has no free spheres to distribute; build the scene first')
    if axis is None:
        extent = [max(b.state.pos[a] for b in spheres) - min(b.state.pos[a] for b in spheres) for a in range(3)]
        axis = extent.index(max(extent))
    spheres.sort(key=lambda b: (b.state.pos[axis], b.id))
    counts = [0] * workers
    for k, b in enumerate(spheres):
        w = k * workers // len(spheres)
        b.subdomain = w + 1
        counts[w] += 1
    absolute_verlet_distance()
    move_boundaries_on_workers()
    assigned = set(b.id for b in spheres)
    for b in O.bodies:
        if b and b.id not in assigned and not getattr(b, 'isSubdomain', False):
            b.subdomain = 0
    return counts


def move_boundaries_on_workers():
    """Put a ViscBridgeBoundaryMotion right after NewtonIntegrator in O.engines (unless one is there):
    it moves the master's walls and facets that kinematic engines drive (a drum's RotationEngine) on
    every worker as NewtonIntegrator moves them on the master, which YADE's NewtonIntegrator does not
    (it moves the bodies of its own subdomain only).  Without it ViscBridge refuses such a scene under
    mpy.  :func:`decompose` calls it; with ``mp.DOMAIN_DECOMPOSITION = True`` call it yourself.  Returns
    whether it added the engine."""
    from yade import O
    import yade.wrapper as yw
    engines = list(O.engines)
    newton = [k for k, e in enumerate(engines) if isinstance(e, yw.NewtonIntegrator)]
    if not newton or any(isinstance(e, yw.ViscBridgeBoundaryMotion) for e in engines):
        return False
    O.engines = engines[:newton[-1] + 1] + [yw.ViscBridgeBoundaryMotion(label='boundaryMotion')] + engines[newton[-1] + 1:]
    return True


def energy():
    """``O.energy`` of the whole scene as a dict: under mpy each rank books the energy of its own
    bodies and interactions, and this sums them (in rank order, the same on every rank).  A
    collective: call it on every rank, at the same point.  Serially: ``dict(O.energy.items())``."""
    from yade import O
    mine = dict(O.energy.items())
    mp = _mpy()
    if not mp:
        return mine
    total = {}
    for part in mp.comm.allgather(mine):
        for k, v in part.items():
            total[k] = total.get(k, 0.0) + v
    return total


def energy_total():
    """``O.energy.total()`` of the whole scene (see :func:`energy`); a collective under mpy."""
    return sum(energy().values())


def to_serial():
    """Make a scene merged by mpy (``mp.mpirun(..., withMerge=True)`` on rank 0, or such a scene
    saved and loaded again) a plain serial scene: every body back in subdomain 0 and mpy's
    Subdomain bodies removed.  YADE's NewtonIntegrator never moves a body of another subdomain than
    the scene's, so without this a merged scene run on serially would stand still (ViscBridge's
    guard and time stepper refuse to run it).  The scene is then serial for good: do not pass it to
    ``mp.mpirun`` again (mpy needs its Subdomain bodies).  Returns the number of bodies reassigned."""
    from yade import O
    from yade.wrapper import ViscBridgeTimeStepper
    if getattr(O, 'splitted', False):
        raise RuntimeError('to_serial(): the scene is still split over the ranks; merge it first (mp.mpirun(..., withMerge=True))')
    moved = 0
    for b in O.bodies:
        if b is not None and not getattr(b, 'isSubdomain', False) and b.subdomain != 0:
            b.subdomain = 0
            moved += 1
    for i in [b.id for b in O.bodies if b is not None and getattr(b, 'isSubdomain', False)]:
        O.bodies.erase(i)
    O._sceneObj.subdomain = 0
    for e in O.engines:  # it saved one rank's part of the mode: start afresh on the whole scene
        if isinstance(e, ViscBridgeTimeStepper):
            e.reset()
    return moved


def _merge_only_complete_runs(mp):
    """Wrap ``mp.mpirun`` (once) so that a rank whose run stopped early raises instead of merging.

    When every rank refuses the first step (a particle left to the master, a clump, a bad value),
    YADE's O.run(n, True) re-raises the engine's exception on some ranks but can return normally on
    another (its wait() misses an error thrown before it first polls).  That rank then went on into
    mpirun's mergeScene() and waited for the others' bodies for ever, in about 1 run in 10.  Here it
    sees the run is incomplete (O.iter short of its steps) and raises the same error the guard kept,
    so every rank leaves mpirun."""
    if getattr(mp.mpirun, '_viscbridge_merge_check', False):
        return
    original = mp.mpirun

    def mpirun(nSteps, np=None, withMerge=False):
        from yade import O
        start, merge = O.iter, mp.mergeScene

        def merge_after_a_complete_run():
            if O.iter - start < nSteps:
                import yade.wrapper as yw
                kept = [e.lastError for e in O.engines if isinstance(e, yw.ViscBridgeGuard) and e.lastError]
                raise RuntimeError(kept[0] if kept else 'the run stopped at step %d, %d steps short of the %d asked: not '
                                   'merged' % (O.iter, start + nSteps - O.iter, nSteps))
            merge()
        mp.mergeScene = merge_after_a_complete_run
        try:
            return original(nSteps, np, withMerge)
        finally:
            mp.mergeScene = merge
    mpirun.__doc__ = original.__doc__
    mpirun._viscbridge_merge_check = True
    mp.mpirun = mpirun


if _launched_by_mpiexec():
    from yade import mpy as _mp
    _merge_only_complete_runs(_mp)
