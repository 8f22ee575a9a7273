"""Liquid bridges for ParaView, beside YADE's own VTKRecorder output.

    from yade import O
    import viscbridge.vtk
    O.engines = O.engines + [viscbridge.vtk.bridge_recorder('out/wet-', iterPeriod=1000)]

writes ``out/wet-bridges.<iter>.vtp`` (VTK XML PolyData) and ``out/wet-bridges.pvd``, the time
series ParaView opens in one go (File ▸ Open ▸ ``wet-bridges.pvd``), and the spheres with their
liquid and agglomerate label in ``out/wet-particles.*`` (:func:`write_particles`).  Every ViscBridge interaction
is a line from body 1 to body 2 — sphere centres, or the foot of the bridge on a wall, facet or
box — with its state as cell data: every output field of the per-contact record (``_registry.RECORD``:
``bridge``, ``separation``, ``cn``, ``ct``, ``cr``, the contact, viscous and capillary forces on
body 1 [N], ...), ``gap`` (S [m], the scalar ParaView colours by first), the bridge's liquid
``bridgeVolume`` [m³] and rupture distance ``sRup`` [m], ``viscousForce`` (the magnitude of the
viscous force) and the body ids.  Load it with YADE's ``VTKRecorder`` files (spheres, walls) to
colour the bridges of a packing by their gap or force.
"""
import math
import os
import xml.etree.ElementTree as ET

from .measures import bridge_segments as _bridges  # the bridges' end points (measures.py)

__all__ = ['write_bridges', 'write_particles', 'BridgeSeries', 'bridge_recorder']

from ._registry import RECORD

# One source of truth: what each contact records is listed once (core/pair/PairRecord.hpp); every
# output field of it becomes a cell array, plus the per-bridge constants a user colours by.
_KIND = {'Real': ('Float64', 1), 'Vector3r': ('Float64', 3), 'bool': ('Int32', 1)}
CELL_FIELDS = tuple((name, *_KIND[spec['type']]) for name, spec in RECORD.items() if spec['output']) + (
    ('bridgeVolume', 'Float64', 1), ('sRup', 'Float64', 1))


def _array(parent, name, values, components=1, kind='Float64'):
    a = ET.SubElement(parent, 'DataArray', type=kind, Name=name, format='ascii')
    if components > 1:
        a.set('NumberOfComponents', str(components))
    a.text = ' '.join(repr(float(v)) if kind == 'Float64' else str(int(v)) for v in values)


def write_bridges(path, only_bridges=False):
    """Write the current ViscBridge interactions of O to `path` (.vtp); returns their number."""
    rows = _bridges(only_bridges)
    root = ET.Element('VTKFile', type='PolyData', version='0.1', byte_order='LittleEndian')
    piece = ET.SubElement(ET.SubElement(root, 'PolyData'), 'Piece', NumberOfPoints=str(2 * len(rows)),
                          NumberOfLines=str(len(rows)), NumberOfVerts='0', NumberOfStrips='0', NumberOfPolys='0')
    _array(ET.SubElement(piece, 'Points'), 'Points', [c for a, b, _, _ in rows for c in (*a, *b)], 3)
    lines = ET.SubElement(piece, 'Lines')
    _array(lines, 'connectivity', range(2 * len(rows)), kind='Int64')
    _array(lines, 'offsets', range(2, 2 * len(rows) + 1, 2), kind='Int64')
    cells = ET.SubElement(piece, 'CellData', Scalars='gap')
    _array(cells, 'gap', [ph.separation for _, _, ph, _ in rows])
    for name, kind, components in CELL_FIELDS:
        values = [getattr(ph, name) for _, _, ph, _ in rows]
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
    by liquid or agglomerate."""
    from yade import O
    import yade.wrapper as yw
    from . import liquid
    from .analysis.agglomerates import agglomerates
    spheres = [b for b in O.bodies if b is not None and isinstance(b.shape, yw.Sphere)]
    spread = liquid.distribution()
    per_sphere = dict(zip(spread.ids.tolist(), spread.liquid.tolist()))
    groups = agglomerates()

    def label(b):
        try:
            return groups.label_of(b.clumpId if b.isClumpMember else b.id)
        except KeyError:
            return -1
    root = ET.Element('VTKFile', type='PolyData', version='0.1', byte_order='LittleEndian')
    piece = ET.SubElement(ET.SubElement(root, 'PolyData'), 'Piece', NumberOfPoints=str(len(spheres)),
                          NumberOfVerts=str(len(spheres)), NumberOfLines='0', NumberOfStrips='0', NumberOfPolys='0')
    _array(ET.SubElement(piece, 'Points'), 'Points', [c for b in spheres for c in b.state.pos], 3)
    verts = ET.SubElement(piece, 'Verts')
    _array(verts, 'connectivity', range(len(spheres)), kind='Int64')
    _array(verts, 'offsets', range(1, len(spheres) + 1), kind='Int64')
    data = ET.SubElement(piece, 'PointData', Scalars='liquid')
    _array(data, 'radius', [b.shape.radius for b in spheres])
    _array(data, 'film', [getattr(b.state, 'film', 0.0) for b in spheres])
    _array(data, 'liquid', [per_sphere.get(b.id, 0.0) for b in spheres])
    _array(data, 'agglomerate', [label(b) for b in spheres], kind='Int64')
    _array(data, 'id', [b.id for b in spheres], kind='Int64')
    _write(root, path)
    return len(spheres)


class BridgeSeries:
    """Files ``<prefix>bridges.<iter>.vtp`` and ``<prefix>particles.<iter>.vtp`` and the collections
    ``<prefix>bridges.pvd`` and ``<prefix>particles.pvd`` that give ParaView their simulated times."""

    def __init__(self, prefix, only_bridges=False, particles=True):
        self.prefix, self.only_bridges, self.particles, self.steps = prefix, only_bridges, particles, []

    @property
    def collection(self):
        return self.prefix + 'bridges.pvd'

    def record(self, after_step=False):
        """Write the scene's bridges (and spheres) now.  Called from the recorder's PyRunner, which runs
        after the integrator (`after_step`): the positions are then those of the next step, so the
        frame is numbered and timed as that step — a run of N steps ends with frame N."""
        from yade import O
        iteration, time = (O.iter + 1, O.time + O.dt) if after_step else (O.iter, O.time)
        path = '%sbridges.%010d.vtp' % (self.prefix, iteration)
        write_bridges(path, self.only_bridges)
        if self.particles:
            write_particles('%sparticles.%010d.vtp' % (self.prefix, iteration))
        if not (self.steps and self.steps[-1][1] == path):
            self.steps.append((time, path))
        self._write_collections()
        return path

    def _write_collections(self):
        kinds = ('bridges', 'particles') if self.particles else ('bridges',)
        for kind in kinds:
            collection = self.prefix + kind + '.pvd'
            root = ET.Element('VTKFile', type='Collection', version='0.1', byte_order='LittleEndian')
            coll = ET.SubElement(root, 'Collection')
            base = os.path.dirname(os.path.abspath(collection))
            for t, path in self.steps:
                path = path.replace(self.prefix + 'bridges.', self.prefix + kind + '.')
                ET.SubElement(coll, 'DataSet', timestep=repr(t) if math.isfinite(t) else '0', group='', part='0',
                              file=os.path.relpath(os.path.abspath(path), base))
            _write(root, collection)


_SERIES = {}


def bridge_recorder(prefix, iterPeriod=None, virtPeriod=None, only_bridges=False, particles=True):
    """A PyRunner writing the bridges every `iterPeriod` steps (or `virtPeriod` seconds of simulated
    time) to ``<prefix>bridges.*.vtp`` and ``<prefix>bridges.pvd`` — and, with `particles`, the
    spheres with their liquid and agglomerate to ``<prefix>particles.*.vtp`` and
    ``<prefix>particles.pvd``; append it to O.engines."""
    import yade.wrapper as yw
    from . import _checks
    if (iterPeriod is None) == (virtPeriod is None):
        raise ValueError('bridge_recorder: give exactly one of iterPeriod=... (steps) or virtPeriod=... [s]')
    if not isinstance(prefix, str) or not prefix:
        _checks.reject('bridge_recorder', 'prefix', prefix, 'a non-empty path prefix')
    _checks.boolean('bridge_recorder', 'particles', particles)
    series = _SERIES[prefix] = BridgeSeries(prefix, only_bridges, particles)
    command = 'import viscbridge.vtk; viscbridge.vtk._SERIES[%r].record(after_step=True)' % prefix
    if iterPeriod is not None:
        period = _checks.integer('bridge_recorder', 'iterPeriod', iterPeriod, minimum=1)
    else:
        virtPeriod = _checks.positive('bridge_recorder', 'virtPeriod', virtPeriod, ' [s]')
    from yade import O
    series.record()  # the state the run starts from
    if iterPeriod is None:
        return yw.PyRunner(virtPeriod=virtPeriod, command=command)
    # The runner ends steps O.iter + period - 1, + 2·period - 1, ...: frames O.iter + period, ...
    first = O.iter + period - 1
    return yw.PyRunner(iterPeriod=period, firstIterRun=first, initRun=first == 0, command=command)
