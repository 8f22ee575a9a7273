"""viscbridge.vtk writes the bridges as VTK PolyData that ParaView reads, with their state."""
import os
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
