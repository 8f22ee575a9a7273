"""viscbridge.vtk writes the bridges as VTK PolyData that ParaView reads, with their state."""
import os
import time
import xml.etree.ElementTree as ET

import pytest
from yade import O, utils

import yade.wrapper as yw

import viscbridge
import viscbridge.vtk as vtk
from wetpairs import R, material


def arrays(path):
    piece = ET.parse(path).getroot().find('PolyData/Piece')
    out = {a.get('Name'): [float(x) for x in a.text.split()] if a.text else [] for a in piece.iter('DataArray')}
    return piece, out


def wet_pair_and_wall():
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat), utils.sphere((0, 0, 0.999 * R), R, material=mat),
                     utils.sphere((0, 0, 2.998 * R), R, material=mat)])
    O.bodies[2].state.vel = (0, 0, -0.01)
    O.engines = viscbridge.engines(viscosity=1.0, gravity=(0, 0, -9.81))
    O.dt = 1e-9


def test_bridges_are_lines_with_their_state(tmp_path):
    wet_pair_and_wall()
    O.run(20, True)
    path = str(tmp_path / 'b.vtp')
    count = vtk.write_bridges(path)
    intrs = [i for i in O.interactions if i.isReal]
    assert count == len(intrs) == 2
    piece, a = arrays(path)
    assert piece.get('NumberOfLines') == '2' and piece.get('NumberOfPoints') == '4'
    for k, i in enumerate(intrs):
        assert a['gap'][k] == pytest.approx(i.phys.separation)
        assert a['bridge'][k] == 1
        assert a['normalViscousForce'][3 * k:3 * k + 3] == pytest.approx(list(i.phys.normalViscousForce))
        assert a['id1'][k] == i.id1 and a['id2'][k] == i.id2
        end1, end2 = a['Points'][6 * k:6 * k + 3], a['Points'][6 * k + 3:6 * k + 6]
        # sphere ends at the centres, a wall end at the wall's surface below its sphere
        for end, body in ((end1, O.bodies[i.id1]), (end2, O.bodies[i.id2])):
            if isinstance(body.shape, yw.Sphere):
                assert end == pytest.approx(list(body.state.pos), abs=1e-12)
            else:
                assert end[2] == pytest.approx(0, abs=1e-9)


def test_recorder_writes_a_time_series_paraview_can_open(tmp_path):
    wet_pair_and_wall()
    prefix = str(tmp_path / 'out' / 'wet-')
    O.engines = O.engines + [vtk.bridge_recorder(prefix, iterPeriod=10)]
    O.run(30, True)
    coll = ET.parse(prefix + 'bridges.pvd').getroot().find('Collection')
    sets = coll.findall('DataSet')
    # the starting state and the end of steps 10, 20 and 30: a run of 30 steps ends with its last frame
    assert [s.get('file')[-14:-4] for s in sets] == ['%010d' % i for i in (0, 10, 20, 30)]
    times = [float(s.get('timestep')) for s in sets]
    assert times[0] == 0 and times == sorted(times) and times[-1] == pytest.approx(O.time, rel=1e-12)
    for s in sets:
        assert os.path.isfile(os.path.join(os.path.dirname(prefix), s.get('file')))
    piece, a = arrays(os.path.join(os.path.dirname(prefix), sets[-1].get('file')))
    bridges = [i for i in O.interactions if i.isReal]
    assert a['bridgeVolume'] == pytest.approx([i.phys.bridgeVolume for i in bridges]) and min(a['bridgeVolume']) > 0
    assert a['capillaryForce'] == pytest.approx([c for i in bridges for c in i.phys.capillaryForce])


def test_every_output_of_the_contact_record_is_a_cell_array(tmp_path):
    from viscbridge._registry import RECORD
    wet_pair_and_wall()
    O.run(2, True)
    path = str(tmp_path / 'b.vtp')
    vtk.write_bridges(path)
    _, a = arrays(path)
    outputs = [name for name, spec in RECORD.items() if spec['output']]
    assert 'capillaryForce' in outputs and set(outputs) <= set(a)


def test_recorder_arguments():
    with pytest.raises(ValueError, match='exactly one'):
        vtk.bridge_recorder('x-')
    with pytest.raises(ValueError, match='iterPeriod'):
        vtk.bridge_recorder('x-', iterPeriod=0)
    for flag in ('only_bridges', 'particles', 'boundary'):
        with pytest.raises(ValueError, match=flag):
            vtk.bridge_recorder('x-', iterPeriod=1, **{flag: 'yes'})


def test_particles_carry_their_liquid_and_agglomerate(tmp_path):
    import viscbridge.liquid as liquid
    wet_pair_and_wall()
    O.engines = viscbridge.engines(viscosity=1.0, gravity=(0, 0, -9.81), liquidModel='film')
    O.dt = 1e-9
    liquid.set_film([1, 2], [1e-12, 3e-12])
    O.run(20, True)
    path = str(tmp_path / 'p.vtp')
    assert vtk.write_particles(path) == 2
    piece, a = arrays(path)
    assert a['id'] == [1, 2] and a['radius'] == pytest.approx([R, R])
    d = liquid.distribution()
    assert a['liquid'] == pytest.approx(list(d.liquid)) and sum(a['liquid']) == pytest.approx(liquid.total(), rel=1e-12)
    assert a['agglomerate'] == [0, 0]  # bridged to each other; the wall joins nothing


def frames(collection):
    """(iteration, time, file) of each data set of a .pvd, in its order."""
    sets = ET.parse(collection).getroot().find('Collection').findall('DataSet')
    return [(int(s.get('file')[-14:-4]), float(s.get('timestep')), s.get('file')) for s in sets]


def test_a_contact_without_a_bridge_holds_no_liquid(tmp_path):
    """A dry contact's ViscBridgePhys.bridgeVolume is the largest volume a bridge forming there may
    take, not liquid: summed over the file it gave several times the liquid in the bridges."""
    import viscbridge.liquid as liquid
    mat = material()
    O.bodies.append([utils.wall(0, axis=2, material=mat)] +
                    [utils.sphere((0, 0, (0.999 + 1.998 * k) * R), R, material=mat) for k in range(4)])
    O.engines = viscbridge.engines(viscosity=1.0, gravity=(0, 0, -9.81), liquidModel='film')
    O.dt = 1e-9
    liquid.set_film([1, 2], 1e-12)  # spheres 3 and 4 carry none
    liquid.make_dry(ids=[0])        # nor does the wall take any
    O.run(20, True)
    contacts = {(i.id1, i.id2): i.phys for i in O.interactions if i.isReal}
    dry = [k for k, ph in contacts.items() if not ph.bridge]
    assert len(contacts) == 4 and 0 < len(dry) < 4 and all(contacts[k].bridgeVolume > 0 for k in dry)
    path = str(tmp_path / 'b.vtp')
    vtk.write_bridges(path)
    _, a = arrays(path)
    assert sum(a['bridgeVolume']) == pytest.approx(liquid.in_bridges(), rel=1e-12) and liquid.in_bridges() > 0
    for k, ends in enumerate(zip(a['id1'], a['id2'])):
        wet = contacts[tuple(int(i) for i in ends)].bridge
        assert a['bridge'][k] == wet
        if not wet:
            assert a['bridgeVolume'][k] == 0 and a['sRup'][k] == 0
    vtk.write_particles(str(tmp_path / 'p.vtp'))
    _, p = arrays(str(tmp_path / 'p.vtp'))
    assert sum(p['liquid']) == pytest.approx(liquid.total(), rel=1e-12)


def test_a_run_that_ends_between_periods_ends_with_its_last_frame(tmp_path):
    wet_pair_and_wall()
    prefix = str(tmp_path / 'wet-')
    O.engines = O.engines + [vtk.bridge_recorder(prefix, iterPeriod=10)]
    O.run(25, True)
    O.run(5, True)   # ends on a period: one frame for step 30
    O.run(3, True)
    for kind in ('bridges', 'particles', 'boundary'):
        listed = frames(prefix + kind + '.pvd')
        assert [i for i, _, _ in listed] == [0, 10, 20, 25, 30, 33]
        assert listed[-1][1] == pytest.approx(O.time, rel=1e-12)
        assert all(os.path.isfile(os.path.join(str(tmp_path), f)) for _, _, f in listed)
    _, a = arrays(prefix + 'bridges.%010d.vtp' % 33)
    assert a['gap'] == pytest.approx([i.phys.separation for i in O.interactions if i.isReal])


def test_a_run_to_a_time_ends_with_its_last_frame(tmp_path):
    wet_pair_and_wall()
    prefix = str(tmp_path / 'wet-')
    O.run(2, True)  # the time stepper has set dt
    O.engines = O.engines + [vtk.bridge_recorder(prefix, virtPeriod=10 * O.dt)]
    O.stopAtTime = O.time + 25.5 * O.dt
    O.run(-1, True)
    listed = frames(prefix + 'bridges.pvd')
    assert listed[-1][0] == O.iter and listed[-1][1] == pytest.approx(O.time, rel=1e-12)
    assert [i for i, _, _ in listed] == sorted({i for i, _, _ in listed}) and len(listed) >= 3  # no step twice


def test_a_run_paused_by_an_engine_and_a_single_step_end_with_their_frames(tmp_path):
    """An engine before the recorder pauses the run (as Settling.run does when the run turns
    unstable): the step it paused in is the run's last; O.step() is a run of one step."""
    wet_pair_and_wall()
    prefix = str(tmp_path / 'wet-')
    pause = yw.PyRunner(iterPeriod=1, command='import yade; yade.O.pause() if yade.O.iter == 6 else None')
    O.engines = O.engines + [pause, vtk.bridge_recorder(prefix, iterPeriod=10)]
    O.run(100, True)
    while O.subStep >= 0:  # O.run returns once the pause is asked for, the step may still be ending
        time.sleep(0.001)
    O.engines = O.engines[:-2] + O.engines[-1:]
    O.step()
    assert O.iter == 8 and [i for i, _, _ in frames(prefix + 'bridges.pvd')] == [0, 7, 8]


def test_the_boundary_of_a_turned_drum_is_where_the_drum_now_is(tmp_path):
    """The drum's facets as triangles at their current vertices (turned with the drum) and its end
    walls as rectangles over the drum, a file per frame listed in <prefix>boundary.pvd."""
    from yade import Quaternion, Vector3
    import viscbridge.scenes as scenes
    d = scenes.drum(radius=R, drumRadius=8 * R, length=4 * R, n=4, rpm=120, segments=8)
    def corners(i):
        s = O.bodies[i].state
        return [s.pos + s.ori * v for v in O.bodies[i].shape.vertices]
    before = {i: corners(i) for i in d.facets}
    prefix = str(tmp_path / 'drum-')
    O.engines = O.engines + [vtk.bridge_recorder(prefix, virtPeriod=0.004)]
    d.run(duration=0.01)
    angle = d.omega * O.time
    assert angle > 0.1
    listed = frames(prefix + 'boundary.pvd')
    assert listed[-1][0] == O.iter
    piece, a = arrays(os.path.join(str(tmp_path), listed[-1][2]))
    polys = piece.find('Polys')
    offsets = [int(x) for x in polys.find("DataArray[@Name='offsets']").text.split()]
    connectivity = [int(x) for x in polys.find("DataArray[@Name='connectivity']").text.split()]
    points = [Vector3(*a['Points'][3 * k:3 * k + 3]) for k in range(len(a['Points']) // 3)]
    cells = [[points[j] for j in connectivity[start:end]] for start, end in zip([0] + offsets[:-1], offsets)]
    kind = dict(zip(a['id'], a['shape']))
    assert sorted(int(i) for i, s in kind.items() if s == 1) == sorted(d.facets)
    turn = Quaternion((0, 1, 0), angle)
    for cell, i, shape in zip(cells, a['id'], a['shape']):
        if shape == 1:  # a facet: its corners now, the initial ones turned by the drum's angle
            assert len(cell) == 3
            for now, written, first in zip(corners(int(i)), cell, before[int(i)]):
                assert (written - now).norm() < 1e-12 * d.params['drumRadius']
                assert (written - turn * first).norm() < 1e-5 * d.params['drumRadius']
                assert (written - first).norm() > 0.05 * d.params['drumRadius']
        else:           # an end wall: a rectangle in its plane spanning the drum's facets
            assert shape == 2 and len(cell) == 4
            assert {round(p[1] / R, 9) for p in cell} in ({-2.0}, {2.0})
            for k in (0, 2):
                drum = [p[k] for f in d.facets for p in corners(f)]
                assert sorted({p[k] for p in cell}) == pytest.approx([min(drum), max(drum)], rel=1e-12)
