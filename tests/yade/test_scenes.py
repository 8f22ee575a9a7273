"""viscbridge.scenes: the settling scene, periodic or walled, its runs and its output, and the names
and logging hook it keeps since it became a package (scenes saved during a run call the hook)."""
import csv
import math

import pytest
from yade import O, plot
import yade.wrapper as yw

import viscbridge.scenes as scenes
from wetpairs import R


def test_periodic_settling_runs_on_a_floor_of_fixed_spheres():
    s = scenes.settling(n=40, periodic=True, viscosity=1.0, seed=2, integration='implicit')
    assert O.periodic
    floor = [O.bodies[i] for i in s.walls]
    assert floor and all(not b.dynamic for b in floor)
    rf, z_floor = floor[0].shape.radius, floor[0].state.pos[2]
    why = s.run(duration=0.03)
    assert why is None, why
    dynamic = [b for b in O.bodies if b.dynamic]
    # lowest a sphere can sit: in the hollow between four floor spheres (square lattice, spacing 2 r_f)
    assert all(b.state.pos[2] - z_floor > 0.99 * math.sqrt((b.shape.radius + rf) ** 2 - 2 * rf ** 2) for b in dynamic), \
        'a sphere went through the floor'
    assert any(i.isReal and i.phys.bridge and (i.id1 in s.walls or i.id2 in s.walls) for i in O.interactions)
    assert s.kinetic_energy() < s.released_energy()
    # the cell keeps the column's full height (SpherePack.toSimulation would make it the cloud's)
    assert O.cell.hSize[2, 2] > 2 * max(b.state.pos[2] for b in dynamic)


def test_a_run_stopped_by_the_guard_returns_its_diagnosis():
    s = scenes.settling(n=40, viscosity=1.0, dt=2.5 * 1.389e-7)
    why = s.run(duration=0.01)
    assert why.startswith('ViscBridgeGuard stopped the run') and 'Body #' in why
    assert s.stopped_at == pytest.approx(O.time)
    assert O.time < 0.01


def test_settle_stops_when_the_particles_are_at_rest():
    s = scenes.settling(n=30, viscosity=1.0, integration='implicit', seed=4)
    why, at_rest = s.settle(0.1)
    assert why is None and at_rest
    assert s.kinetic_energy() < 1e-3 * max(plot.data['Ek'])
    assert O.time < 0.1


def test_log_limits_follow_the_data_not_the_zero_at_the_start():
    series = [[0.0, 1e-8, 1e-6, 1e-4, 1e-5], [0.0, 3e-9, 2e-4]]
    lo, hi = scenes.log_limits(series)
    assert 1e-9 < lo <= 3e-9 / 2 * 1.0001 and 2e-4 < hi <= 4e-4
    lo, hi = scenes.log_limits([[1e-300, 1.0]], decades=6)
    assert lo == pytest.approx(0.5e-6)
    assert scenes.log_limits([[0.0, -1.0]]) is None


def test_save_writes_every_logged_row(tmp_path):
    s = scenes.settling(n=20, viscosity=1.0, integration='implicit')
    s.run(steps=100, points=10)
    csv_path, png_path = s.save(str(tmp_path / 'sub' / 'run'))
    with open(csv_path) as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(plot.data['t']) >= 10
    assert all(math.isfinite(float(r['Ek'])) for r in rows)
    with open(png_path, 'rb') as fh:
        assert fh.read(8) == b'\x89PNG\r\n\x1a\n'


def test_periodic_settling_runs_explicitly_too():
    s = scenes.settling(n=40, periodic=True, viscosity=1.0, seed=2)
    assert s.run(duration=0.002) is None
    assert all(math.isfinite(c) for b in O.bodies for c in b.state.pos)


# --- the module's names, kept through the split into scenes/ ----------------------------------------
NAMES_BEFORE = {  # their own definitions before viscbridge.scenes became a package
    'viscbridge.scenes': 'Settling _ACTIVE _LOG_COMMAND _check_settling_args _checks _floor_of_spheres _log '
                         'bridge_parameters capillary_input criteria engines instability log_limits plot_history '
                         'settling write_history_csv',
    'viscbridge.engine_list': '_checks _detection_range bridge_parameters criteria engines ip2_defaults',
}


@pytest.mark.parametrize('module', sorted(NAMES_BEFORE))
def test_every_name_of_the_module_is_still_there(module):
    import importlib
    m = importlib.import_module(module)
    assert [n for n in NAMES_BEFORE[module].split() if not hasattr(m, n)] == []


def test_the_logging_command_of_saved_scenes_still_runs():
    """Settling.run logs through a PyRunner with this command, which a scene saved during a run
    holds: it must keep running (and do nothing without an active run)."""
    assert scenes._LOG_COMMAND == 'import viscbridge.scenes; viscbridge.scenes._log()'
    scenes.settling(n=10, viscosity=0.1)
    O.engines = O.engines + [yw.PyRunner(iterPeriod=1, command=scenes._LOG_COMMAND)]
    O.run(3, True)
    assert O.iter == 3
