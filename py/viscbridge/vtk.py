"""Liquid bridges, particles and the boundary for ParaView, a file per frame and a time series each.

This recorder::

    from yade import O
    import viscbridge.vtk
    O.engines = O.engines + [viscbridge.vtk.bridge_recorder('out/wet-', iterPeriod=1000)]

writes, every 1000 steps and at the end of every run, three VTK XML PolyData files per frame and a
``.pvd`` collection of each, the time series ParaView opens in one go (File ▸ Open ▸
``wet-bridges.pvd``, ``wet-particles.pvd``, ``wet-boundary.pvd``):

- ``out/wet-bridges.<iter>.vtp`` (:func:`write_bridges`): every ViscBridge interaction as a line from
  body 1 to body 2 — sphere centres, or the foot of the bridge on a wall, facet or box — with its
  state as cell data: every output field of the per-contact record (``_registry.RECORD``:
  ``bridge``, ``separation``, ``cn``, ``ct``, ``cr``, the contact, viscous and capillary forces on
  body 1 [N], ...), ``gap`` (S [m], the scalar ParaView colours by first), the liquid of its bridge
  ``bridgeVolume`` [m³] and its rupture distance ``sRup`` [m] (both 0 for a contact without a
  bridge: the column sums to :func:`viscbridge.liquid.in_bridges`), ``viscousForce`` (the magnitude
  of the viscous force) and the body ids;
- ``out/wet-particles.<iter>.vtp`` (:func:`write_particles`): the spheres with their radius, film,
  liquid and agglomerate;
- ``out/wet-boundary.<iter>.vtp`` (:func:`write_boundary`): facets, boxes and walls as polygons where
  they are at that frame (a turning drum turns in ParaView).

A run that ends between two periods (``O.run(n)``, ``O.stopAtTime`` as in ``Drum.run``) ends with
its own frame, and so does a run stopped by Ctrl-C or SIGTERM (:func:`flush`); no step is written
twice.  Under yade.mpy each rank writes its piece of a frame of the split scene and the collections
list the pieces as the frame's parts (docs/cluster.md).
"""
import atexit
import math
import os
import re
import signal
import time
import xml.etree.ElementTree as ET

from .liquid import in_bridge as _liquid  # a contact's liquid: 0 without a bridge
from .measures import bridge_segments as _bridges  # the bridges' end points (measures.py)

__all__ = ['write_bridges', 'write_particles', 'write_boundary', 'piece_path', 'BridgeSeries', 'bridge_recorder', 'flush']

from ._registry import RECORD


def _rupture_distance(ph):
    """sRup of a bridge; 0 without a bridge."""
    return ph.sRup if ph.bridge else 0.0


# One source of truth: what each contact records is listed once (core/pair/PairRecord.hpp); every
# output field of it becomes a cell array, plus two constants of its bridge, read as what they are
# for the bridge: its liquid and its rupture distance, both 0 without a bridge.  The physics holds
# other values there on purpose: a contact without a bridge keeps in bridgeVolume and sRup those of
# the largest bridge that may form on it — the cap under which ViscBridgeLiquid gives a forming
# bridge its volume, and the distance the law's formation test reads (a 'fixed' bridge forms with
# exactly them) — and both are saved with the scene.  Zeroing them at the source would need the cap
# in a new saved attribute (scenes saved before it would no longer load), so the readers ask
# `bridge` first: this writer, and viscbridge.liquid for the totals and the particles' liquid.
_KIND = {'Real': ('Float64', 1), 'Vector3r': ('Float64', 3), 'bool': ('Int32', 1)}
CELL_FIELDS = tuple((name, *_KIND[spec['type']]) for name, spec in RECORD.items() if spec['output']) + (
    ('bridgeVolume', 'Float64', 1), ('sRup', 'Float64', 1))
_BRIDGE_CONSTANTS = {'bridgeVolume': _liquid, 'sRup': _rupture_distance}


def _array(parent, name, values, components=1, kind='Float64'):
    a = ET.SubElement(parent, 'DataArray', type=kind, Name=name, format='ascii')
    if components > 1:
        a.set('NumberOfComponents', str(components))
    a.text = ' '.join(repr(float(v)) if kind == 'Float64' else str(int(v)) for v in values)


def _piece(points=0, verts=0, lines=0, polys=0):
    """A PolyData VTKFile and its one Piece with these counts."""
    root = ET.Element('VTKFile', type='PolyData', version='0.1', byte_order='LittleEndian')
    piece = ET.SubElement(ET.SubElement(root, 'PolyData'), 'Piece', NumberOfPoints=str(points), NumberOfVerts=str(verts),
                          NumberOfLines=str(lines), NumberOfStrips='0', NumberOfPolys=str(polys))
    return root, piece


def _cells(piece, tag, sizes):
    """The connectivity and offsets of `tag` (Verts, Lines, Polys): cells of `sizes` points each,
    numbered in the order of the points."""
    cells = ET.SubElement(piece, tag)
    _array(cells, 'connectivity', range(sum(sizes)), kind='Int64')
    offsets, end = [], 0
    for n in sizes:
        end += n
        offsets.append(end)
    _array(cells, 'offsets', offsets, kind='Int64')


def piece_path(path, rank):
    """The file a rank of a split scene writes for `path` (``a.vtp`` -> ``a.rank<k>.vtp``)."""
    root, ext = os.path.splitext(path)
    return '%s.rank%d%s' % (root, rank, ext or '.vtp')


def write_bridges(path, only_bridges=False):
    """Write the current ViscBridge interactions of O to `path` (.vtp); returns their number.  While
    yade.mpy has the scene split, every rank writes its own piece, :func:`piece_path` (`path`, rank):
    the interactions it accounts for (one between two ranks' bodies on the higher rank, so that the
    pieces hold each once); no communication."""
    from . import mpi
    me = mpi.split_rank()
    rows = [r for r in _bridges(only_bridges) if mpi.accounts_for_pair(r[3].id1, r[3].id2, me)]
    if me is not None:
        path = piece_path(path, me)
    root, piece = _piece(points=2 * len(rows), lines=len(rows))
    _array(ET.SubElement(piece, 'Points'), 'Points', [c for a, b, _, _ in rows for c in (*a, *b)], 3)
    _cells(piece, 'Lines', [2] * len(rows))
    cells = ET.SubElement(piece, 'CellData', Scalars='gap')
    _array(cells, 'gap', [ph.separation for _, _, ph, _ in rows])
    for name, kind, components in CELL_FIELDS:
        read = _BRIDGE_CONSTANTS.get(name, lambda ph, name=name: getattr(ph, name))
        values = [read(ph) for _, _, ph, _ in rows]
        _array(cells, name, [c for v in values for c in v] if components > 1 else values, components, kind)
    _array(cells, 'viscousForce', [(ph.normalViscousForce + ph.shearViscousForce).norm() for _, _, ph, _ in rows])
    _array(cells, 'id1', [i.id1 for _, _, _, i in rows], kind='Int64')
    _array(cells, 'id2', [i.id2 for _, _, _, i in rows], kind='Int64')
    _write(root, path)
    return len(rows)


def _write(root, path):
    """Write the XML tree atomically (a reader never sees half a file)."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = path + '.part'
    ET.ElementTree(root).write(tmp, xml_declaration=True, encoding='utf-8')
    os.replace(tmp, path)


def write_particles(path):
    """Write the spheres of O to `path` (.vtp) as points with point data: ``radius`` [m], ``film``
    [m³] (0 without a film), ``liquid`` (film + its share of each bridge, :func:`viscbridge.liquid.distribution`),
    ``agglomerate`` (label of its agglomerate, 0 = largest; -1 for a sphere that is not a member:
    fixed) and ``id``; returns their number.  In ParaView: Glyph (sphere, scale by radius) coloured
    by liquid or agglomerate.  While yade.mpy has the scene split, a collective (the liquid and the
    agglomerates are the whole scene's): every rank writes its own spheres to
    :func:`piece_path` (`path`, rank)."""
    from yade import O
    import yade.wrapper as yw
    from . import liquid
    from .analysis.agglomerates import agglomerates
    from . import mpi
    me = mpi.split_rank()
    spheres = [b for b in O.bodies if b is not None and isinstance(b.shape, yw.Sphere) and mpi.accounts_for_body(b, me)]
    spread = liquid.distribution()
    per_sphere = dict(zip(spread.ids.tolist(), spread.liquid.tolist()))
    groups = agglomerates()
    if me is not None:
        path = piece_path(path, me)

    def label(b):
        try:
            return groups.label_of(b.clumpId if b.isClumpMember else b.id)
        except KeyError:
            return -1
    root, piece = _piece(points=len(spheres), verts=len(spheres))
    _array(ET.SubElement(piece, 'Points'), 'Points', [c for b in spheres for c in b.state.pos], 3)
    _cells(piece, 'Verts', [1] * len(spheres))
    data = ET.SubElement(piece, 'PointData', Scalars='liquid')
    _array(data, 'radius', [b.shape.radius for b in spheres])
    _array(data, 'film', [getattr(b.state, 'film', 0.0) for b in spheres])
    _array(data, 'liquid', [per_sphere.get(b.id, 0.0) for b in spheres])
    _array(data, 'agglomerate', [label(b) for b in spheres], kind='Int64')
    _array(data, 'id', [b.id for b in spheres], kind='Int64')
    _write(root, path)
    return len(spheres)


FACET, WALL, BOX = 1, 2, 3
"""The ``shape`` codes of the boundary file's polygons."""

# a box's faces as its corners (±x, ±y, ±z as 0/1 bits of the corner's index), each seen from outside
_BOX_FACES = ((0, 2, 6, 4), (1, 5, 7, 3), (0, 4, 5, 1), (2, 3, 7, 6), (0, 1, 3, 2), (4, 6, 7, 5))


def _box_corners(b):
    from yade import Vector3
    e = b.shape.extents
    return [b.state.pos + b.state.ori * Vector3(*(e[a] if k >> a & 1 else -e[a] for a in range(3))) for k in range(8)]


def _facet_corners(b):
    return [b.state.pos + b.state.ori * v for v in b.shape.vertices]


def _extent(bodies, walls):
    """Per axis, (low, high) over the spheres, facets and boxes of `bodies` and the planes of `walls`
    on their own axes; None on an axis nothing bounds."""
    import yade.wrapper as yw
    lo, hi = [math.inf] * 3, [-math.inf] * 3

    def take(point, k, margin=0.0):
        lo[k], hi[k] = min(lo[k], point[k] - margin), max(hi[k], point[k] + margin)
    for b in bodies:
        if isinstance(b.shape, yw.Sphere):
            for k in range(3):
                take(b.state.pos, k, b.shape.radius)
        elif isinstance(b.shape, (yw.Facet, yw.Box)):
            for p in (_facet_corners(b) if isinstance(b.shape, yw.Facet) else _box_corners(b)):
                for k in range(3):
                    take(p, k)
    for w in walls:
        take(w.state.pos, w.shape.axis)
    return [(lo[k], hi[k]) if lo[k] <= hi[k] else None for k in range(3)]


def _joined(ranges):
    """The (low, high) spanning the given ones (None: unbounded there), None if all are."""
    ranges = [r for r in ranges if r is not None]
    return (min(r[0] for r in ranges), max(r[1] for r in ranges)) if ranges else None


def _wall_rectangle(w, extent):
    """The rectangle of the infinite plane of wall `w` that spans `extent` on its other two axes
    (None if nothing bounds them)."""
    from yade import Vector3
    axis = w.shape.axis
    a, c = [k for k in range(3) if k != axis]
    if extent[a] is None or extent[c] is None:
        return None
    corners = []
    for u, v in ((0, 0), (1, 0), (1, 1), (0, 1)):
        p = [0.0, 0.0, 0.0]
        p[axis], p[a], p[c] = w.state.pos[axis], extent[a][u], extent[c][v]
        corners.append(Vector3(*p))
    return corners


def write_boundary(path):
    """Write the boundary of O to `path` (.vtp) as polygons where it is now: every facet as its
    triangle, every box as its six faces, every wall — an infinite plane — as the rectangle of its
    plane that spans the other bodies (spheres, facets, boxes) and the planes of the other walls;
    cell data ``id`` (the body) and ``shape`` (``FACET`` 1, ``WALL`` 2, ``BOX`` 3).  A wall with nothing
    to span (a scene of walls alone) and other shapes are left out.  Returns the number of polygons.
    While yade.mpy has the scene split, a collective: every rank writes its own bodies (the master's
    walls and facets; the span of every rank's) to :func:`piece_path` (`path`, rank)."""
    from yade import O
    import yade.wrapper as yw
    from . import mpi
    me = mpi.split_rank()
    bodies = [b for b in O.bodies if b is not None and mpi.accounts_for_body(b, me)]
    walls = [b for b in bodies if isinstance(b.shape, yw.Wall)]
    extent = _extent([b for b in bodies if not isinstance(b.shape, yw.Wall)], walls)
    if me is not None:  # a collective: the extent of every rank's own bodies, this rank's piece
        everyone = mpi.allgather(extent)
        extent = [_joined([part[k] for part in everyone]) for k in range(3)]
        path = piece_path(path, me)
    polygons = []  # (corners, id, shape)
    for b in bodies:
        if isinstance(b.shape, yw.Facet):
            polygons.append((_facet_corners(b), b.id, FACET))
        elif isinstance(b.shape, yw.Box):
            corners = _box_corners(b)
            polygons += [([corners[k] for k in face], b.id, BOX) for face in _BOX_FACES]
        elif isinstance(b.shape, yw.Wall):
            rectangle = _wall_rectangle(b, extent)
            if rectangle is not None:
                polygons.append((rectangle, b.id, WALL))
    root, piece = _piece(points=sum(len(p) for p, _, _ in polygons), polys=len(polygons))
    _array(ET.SubElement(piece, 'Points'), 'Points', [c for p, _, _ in polygons for corner in p for c in corner], 3)
    _cells(piece, 'Polys', [len(p) for p, _, _ in polygons])
    data = ET.SubElement(piece, 'CellData', Scalars='shape')
    _array(data, 'id', [i for _, i, _ in polygons], kind='Int64')
    _array(data, 'shape', [s for _, _, s in polygons], kind='Int32')
    _write(root, path)
    return len(polygons)


_WRITERS = {'particles': write_particles, 'boundary': write_boundary}  # and the bridges, with their option


class BridgeSeries:
    """Frames of the scene in files ``<prefix><kind>.<iter>.vtp`` and their collections
    ``<prefix><kind>.pvd`` that give ParaView their simulated times; the kinds are ``bridges``, and
    ``particles`` and ``boundary`` if asked.  ``frames``: (time, iteration, pieces) of each frame
    written; pieces 0 for one file, N for a frame of a scene split over N ranks of yade.mpy, each rank
    writing its piece ``<prefix><kind>.<iter>.rank<k>.vtp`` and the collection listing them as parts of
    the frame (ParaView shows them as one).  Under mpiexec a whole scene (before the split, or merged
    on rank 0) is written by rank 0 alone, and rank 0 writes the collections."""

    def __init__(self, prefix, only_bridges=False, particles=True, boundary=True):
        self.prefix, self.only_bridges = prefix, only_bridges
        self.kinds = ('bridges',) + (('particles',) if particles else ()) + (('boundary',) if boundary else ())
        self.frames = []
        # the command of its recorder (bridge_recorder): the frame at the end of the recorder's step,
        # with all a process that loads the saved scene needs to go on with the series (_record)
        self.command = 'import viscbridge.vtk; viscbridge.vtk._record(%r, %r, %r, %r)' % (
            _absolute_prefix(prefix), only_bridges, particles, boundary)

    @classmethod
    def resumed(cls, prefix, only_bridges, particles, boundary):
        """The series of `prefix` as its collections on disk hold it: for a recorder saved with its
        scene and run in another process (O.load), which adds frames to the same collections."""
        series = cls(prefix, only_bridges, particles, boundary)
        collection = prefix + 'bridges.pvd'
        frames = {}
        if os.path.exists(collection):
            for entry in ET.parse(collection).getroot().iter('DataSet'):
                found = re.search(r'\.(\d+)(\.rank\d+)?\.vtp$', entry.get('file', ''))
                if found:
                    _, pieces = frames.get(int(found.group(1)), (0, 0))
                    frames[int(found.group(1))] = (float(entry.get('timestep')), pieces + 1 if found.group(2) else 0)
        series.frames = [(t, iteration, pieces) for iteration, (t, pieces) in sorted(frames.items())]
        return series

    def last_step(self):
        """The step of its latest frame (-1: none yet)."""
        return max((f[1] for f in self.frames), default=-1)

    def path(self, kind, iteration):
        return '%s%s.%010d.vtp' % (self.prefix, kind, iteration)

    def record(self, after_step=False):
        """Write the scene's frame now; returns the bridges file.  Called from the recorder, which runs
        after the integrator (`after_step`): the positions are then those of the next step, so the
        frame is numbered and timed as that step — a run of N steps ends with frame N.  Written again
        at the same step, a frame replaces its files and stays one entry of the collections."""
        from yade import O
        iteration, time_ = (O.iter + 1, O.time + O.dt) if after_step else (O.iter, O.time)
        if self.last_step() > iteration:
            raise RuntimeError(
                'bridge_recorder: %sbridges.pvd has frames up to step %d, past this scene\'s step %d: the scene was saved '
                'earlier and run on from there before, or the series belongs to another run. A run branched from a saved '
                'state needs a series of its own: remove the recorder whose command names this prefix from O.engines and '
                'make a new vtk.bridge_recorder(...) with another prefix.' % (self.prefix, self.last_step(), iteration))
        from . import mpi
        pieces = mpi.ranks() if mpi.is_split() else 0
        if pieces or mpi.rank() == 0:  # under mpiexec, a whole scene is rank 0's to write
            for kind in self.kinds:
                if kind == 'bridges':
                    write_bridges(self.path(kind, iteration), self.only_bridges)
                else:
                    _WRITERS[kind](self.path(kind, iteration))
        self.frames = [f for f in self.frames if f[1] != iteration] + [(time_, iteration, pieces)]
        if mpi.rank() == 0:
            self._write_collections()
        return self.path('bridges', iteration)

    def recording(self):
        """Whether its recorder is in O.engines (a scene reset or replaced has stopped it)."""
        from yade import O
        return any(getattr(e, 'command', None) == self.command for e in O.engines)

    def _write_collections(self):
        for kind in self.kinds:
            collection = self.prefix + kind + '.pvd'
            root = ET.Element('VTKFile', type='Collection', version='0.1', byte_order='LittleEndian')
            coll = ET.SubElement(root, 'Collection')
            base = os.path.dirname(os.path.abspath(collection))
            for t, iteration, pieces in self.frames:
                path = self.path(kind, iteration)
                for part, file in enumerate([piece_path(path, k) for k in range(pieces)] if pieces else [path]):
                    ET.SubElement(coll, 'DataSet', timestep=repr(t) if math.isfinite(t) else '0', group='', part=str(part),
                                  file=os.path.relpath(os.path.abspath(file), base))
            _write(root, collection)


_SERIES = {}  # by absolute prefix: the series of this process, where their recorders' commands find them


def _absolute_prefix(prefix):
    """`prefix` from the root, its last part kept as given ('out/' stays a directory, 'out/drum-' a name start)."""
    return os.path.join(os.path.abspath(os.path.dirname(prefix) or '.'), os.path.basename(prefix))


def _record(prefix, only_bridges, particles, boundary):
    """The recorder's command: a frame of the series of `prefix` (absolute) at the end of this step;
    in a process that loaded the saved scene, the series goes on from its collections on disk."""
    series = _SERIES.get(prefix)
    if series is None:
        series = _SERIES[prefix] = BridgeSeries.resumed(prefix, only_bridges, particles, boundary)
        _catch_the_end()
    return series.record(after_step=True)


def bridge_recorder(prefix, iterPeriod=None, virtPeriod=None, only_bridges=False, particles=True, boundary=True):
    """A recorder (:yref:`ViscBridgeRecorder`, a PyRunner) writing a frame every `iterPeriod` steps
    (or `virtPeriod` seconds of simulated time) and at the end of every run — the bridges to
    ``<prefix>bridges.*.vtp`` and ``<prefix>bridges.pvd``; with `particles`, the spheres with their
    liquid and agglomerate to ``<prefix>particles.*``; with `boundary`, facets, boxes and walls to
    ``<prefix>boundary.*`` — starting with the state it is made in; append it to O.engines (after
    the integrator, where ``O.engines + [...]`` puts it).

    The end of a run: the last step of ``O.run(n)`` or of a run to ``O.stopAtTime`` (``Drum.run``,
    ``Settling.run``), a run paused by ``O.pause()`` from an engine before the recorder, and a step of
    ``O.step()`` — each one frame, also when it falls on a period.  A run stopped by Ctrl-C or SIGTERM
    gets its frame from :func:`flush`, which runs at the signal and at the exit of Python."""
    import yade.wrapper as yw
    from . import _checks
    if (iterPeriod is None) == (virtPeriod is None):
        raise ValueError('bridge_recorder: give exactly one of iterPeriod=... (steps) or virtPeriod=... [s]')
    if not isinstance(prefix, str) or not prefix:
        _checks.reject('bridge_recorder', 'prefix', prefix, 'a non-empty path prefix')
    for name, flag in (('only_bridges', only_bridges), ('particles', particles), ('boundary', boundary)):
        _checks.boolean('bridge_recorder', name, flag)
    if iterPeriod is not None:
        period = _checks.integer('bridge_recorder', 'iterPeriod', iterPeriod, minimum=1)
    else:
        virtPeriod = _checks.positive('bridge_recorder', 'virtPeriod', virtPeriod, ' [s]')
    from yade import O
    series = _SERIES[_absolute_prefix(prefix)] = BridgeSeries(prefix, only_bridges, particles, boundary)
    series.record()  # the state the run starts from
    _catch_the_end()
    if iterPeriod is None:
        return yw.ViscBridgeRecorder(virtPeriod=virtPeriod, command=series.command)
    # The runner ends steps O.iter + period - 1, + 2·period - 1, ...: frames O.iter + period, ...
    first = O.iter + period - 1
    return yw.ViscBridgeRecorder(iterPeriod=period, firstIterRun=first, initRun=first == 0, command=series.command)


def flush():
    """Write the current state as a frame of every series whose recorder is in O.engines, unless its
    last frame is this step already; returns the bridges files written.  A running simulation is
    paused first, and the step in progress finishes.  Runs by itself at Ctrl-C (SIGINT), SIGTERM and
    the exit of Python once a recorder exists, so that a run stopped there keeps its last frame; a
    run stopped by an exception in an engine (the guard) gets its frame at the exit, or where you
    call flush() if the script goes on."""
    from yade import O
    from . import mpi
    if mpi.is_split():  # writing a split scene is a collective, and the ranks stop one by one
        return []
    live = [s for s in _SERIES.values() if s.recording()]
    if live:
        _let_the_step_finish(O)
    # a series with frames past this step is another run's (its recorder raised when it ran): left as it is
    return [s.record() for s in live if s.last_step() < O.iter]


def _let_the_step_finish(O):
    """Pause O and let the step in progress finish: O.pause() and Ctrl-C only ask the loop to stop
    after it, and O.run(n, True) returns as soon as they have asked.  YADE says a step is in progress
    by O.subStep >= 0, but an engine that threw (the guard stopping a run) leaves it there for good,
    so the wait is bounded by 20 steps at the run's speed (0.2 to 30 s); the state is then the one
    the exception left."""
    O.pause()
    bound = min(30.0, max(0.2, 20.0 / O.speed)) if O.speed > 0 else 30.0
    end = time.monotonic() + bound
    while O.subStep >= 0 and time.monotonic() < end:
        time.sleep(0.001)


_HOOKED = []


def _catch_the_end():
    """Once per process: flush() at the exit of Python and at SIGINT and SIGTERM, before the
    handler that was there (Python's KeyboardInterrupt; SIGTERM's default, which then still ends
    the process with its status 143).  An ignored signal stays ignored; a handler set later replaces
    this one and the exit still flushes.  From another thread than the main one, only the exit."""
    if _HOOKED:
        return
    _HOOKED.append(True)
    atexit.register(flush)
    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            previous = signal.getsignal(sig)
            if previous is None or previous == signal.SIG_IGN:
                continue  # set outside Python (cannot be chained), or ignored on purpose
            signal.signal(sig, lambda signum, frame, previous=previous: _stopped(signum, frame, previous))
        except ValueError:  # not the main thread
            pass


def _stopped(signum, frame, previous):
    """A signal's handler: the frames, then what the signal did before (also if writing failed)."""
    try:
        flush()
    finally:
        if callable(previous):
            previous(signum, frame)
        else:  # SIG_DFL: its default action, as without the recorder
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
