"""Every ViscBridge engine under YADE's MPI module yade.mpy, against the serial run.

tests/system/mpi_case.py (the settling scene with the time stepper and the guard) runs serially and on
2 and 3 ranks (mpiexec, oversubscribed on this 2-core machine); 3 ranks are the master and two
workers, with bridges across the subdomain boundary.  The distributed runs must give the serial
positions to 1e-9 (relative), the serial dt at every step on every rank, an energy balance summed
over the ranks that closes to 1 %, the serial guard's diagnosis, and must refuse a dt that differs
between the ranks — on every rank, without hanging.
"""
import json
import math
import os
import shutil
import signal
import subprocess
import tempfile
import time

import pytest
import yade.wrapper as yw

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.join(HERE, 'mpi_case.py')
TIMEOUT = 400  # s; a hang is a failure, not a stuck test run
MPIEXEC = ['mpiexec', '--allow-run-as-root', '--oversubscribe']

pytestmark = pytest.mark.skipif(shutil.which('mpiexec') is None, reason='mpiexec is not installed')
# (in one process, without mpy: tests/yade/test_mpi_serial.py)

_cache = {}


def run_group(cmd, timeout=TIMEOUT, **kw):
    """subprocess.run in a process group of its own, all of which is killed on a time-out (mpiexec's
    ranks would otherwise outlive it)."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True, **kw)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        raise AssertionError('%s did not finish within %d s (a rank waiting for the others?)\n%s\n%s'
                             % (cmd, timeout, out[-3000:], err[-3000:]))
    return subprocess.CompletedProcess(cmd, proc.returncode, out, err)


def run_case(ranks, *options, timeout=TIMEOUT, case=CASE):
    """Run `case` (mpi_case.py) on `ranks` ranks (1: serial, without mpy) and return the result of every rank."""
    key = (case, ranks) + options
    if key in _cache:
        return _cache[key]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, 'case')
        yade = ['yade', '-n', '-x', case, out, *options]
        cmd = yade if ranks == 1 else MPIEXEC + ['-n', str(ranks)] + yade
        # a private TMPDIR: mpiexec's session directory is named after its PID, which repeats in
        # yadew's PID namespaces (a leftover of a killed run would make mpiexec fail to start)
        env = dict(os.environ, OMP_NUM_THREADS='1', TMPDIR=tmp)
        proc = run_group(cmd, timeout=timeout, cwd=tmp, env=env)
        results = []
        for r in range(ranks):
            path = '%s.rank%d.json' % (out, r)
            if not os.path.exists(path):
                raise AssertionError('rank %d of %s wrote no result (exit %d)\n--- stdout\n%s\n--- stderr\n%s'
                                     % (r, cmd, proc.returncode, proc.stdout[-3000:], proc.stderr[-3000:]))
            with open(path) as fh:
                results.append(json.load(fh))
    _cache[key] = results
    return results


def max_relative_position_difference(a, b):
    assert sorted(a) == sorted(b)
    return max(max(abs(x - y) for x, y in zip(a[k], b[k])) / max(abs(x) for x in a[k]) for k in a)


def energy_imbalance(result):
    """|Σ O.energy − initial kinetic energy| over the energy put in (the scene starts in motion)."""
    E = result['energy']
    return abs(sum(E.values()) - result['initialKinetic']) / (result['initialKinetic'] + abs(E['gravWork']))


def assert_matches_serial(serial, parallel, position_tolerance=1e-9, dt_tolerance=1e-12):
    s, p = serial[0], parallel[0]
    assert s['error'] is None and all(r['error'] is None for r in parallel), [r['error'] for r in parallel]
    assert p['iter'] == s['iter'] == len(s['dts'])
    assert max_relative_position_difference(s['positions'], p['positions']) <= position_tolerance
    # every rank stepped with the serial dt, step after step
    for r in parallel:
        assert len(r['dts']) == len(s['dts'])
        assert max(abs(a - b) / a for a, b in zip(s['dts'], r['dts'])) <= dt_tolerance
        assert r['dts'] == p['dts']
    assert p['bridges'] == s['bridges']
    assert energy_imbalance(p) <= 0.01
    for k, v in s['energy'].items():  # each term, summed over the ranks, is the serial one
        assert p['energy'][k] == pytest.approx(v, rel=1e-6, abs=1e-12 * s['initialKinetic']), k


@pytest.mark.parametrize('ranks', [2, 3])
def test_explicit_settling_matches_serial(ranks):
    """Explicit, with the time stepper and the guard: the stepper's dt changes along the run (the
    bound over all ranks), the guard checks the whole scene's energy, and the result is the
    serial one."""
    serial, parallel = run_case(1), run_case(ranks)
    assert len(set(serial[0]['dts'])) > 20, 'the time stepper should adapt dt in this scene'
    assert serial[0]['energy']['viscDissipNormal'] > 0.1 * serial[0]['initialKinetic']  # the bridges matter
    assert parallel[0]['guardChecks'] == serial[0]['guardChecks'] > 20
    if ranks == 3:
        assert parallel[0]['crossBridges'] > 0, 'the scene should have bridges between the two workers'
    assert_matches_serial(serial, parallel)


@pytest.mark.parametrize('ranks', [2, 3])
@pytest.mark.parametrize('viscosity,speed', [(1.0, 0.3), (0.01, 1.0)], ids=['bridges', 'contacts'])
def test_implicit_settling_matches_serial(ranks, viscosity, speed):
    """Implicit: one backward-Euler system over all ranks, converged to the same tolerance as the
    serial solve.  The difference is the solver's: at a tolerance of 1e-12 the positions agree to
    1e-9 (at the default 1e-6 they differ by ~2.5e-6 after 300 steps).  At 1 Pa·s the bridges keep
    the spheres apart and dt stays at the Rayleigh bound; at 0.01 Pa·s and 1 m/s contacts form and,
    with the Rayleigh bound moved out of the way (rayleighFraction 1), the stepper changes dt along
    the run, from the contacts of all ranks."""
    options = ('--integration', 'implicit', '--viscosity', str(viscosity), '--speed', str(speed), '--tolerance', '1e-12')
    if viscosity < 0.1:
        options += ('--rayleigh-fraction', '0.8')
    serial, parallel = run_case(1, *options), run_case(ranks, *options)
    assert serial[0]['energy']['viscDissipNormal'] > 0.1 * serial[0]['initialKinetic']
    if viscosity < 0.1:
        assert len(set(serial[0]['dts'])) > 1  # contact stiffness, not the Rayleigh bound, sets dt
    assert parallel[0]['solver']['residual'] <= 1e-12 and parallel[0]['solver']['solves'] == serial[0]['solver']['solves'] == 300
    if ranks == 3:
        assert parallel[0]['crossBridges'] > 0
    # the contacts' dt follows the positions, which carry the solver's tolerance
    assert_matches_serial(serial, parallel, dt_tolerance=1e-12 if viscosity > 0.1 else 1e-9)


def test_bridge_events_on_every_rank():
    """The test engine ViscBridgeEventCounter on 3 ranks: each rank's law publishes the formations and
    ruptures of its interactions, its engines read them in order and they agree with the interactions;
    the workers together see at least the serial run's formations (a bridge across two subdomains is
    on both)."""
    serial, parallel = run_case(1, '--events'), run_case(3, '--events')
    assert all(r['error'] is None for r in serial + parallel), [r['error'] for r in serial + parallel]
    s = serial[0]['events']
    assert s['formed'] > 40 and s['ruptured'] > 0
    for r in serial + parallel:
        assert r['events']['mismatches'] == 0 and r['events']['outOfOrder'] == 0, r
    workers = [r['events'] for r in parallel if r['rank'] > 0]
    assert sum(e['formed'] for e in workers) >= s['formed']
    assert all(e['formed'] > 0 for e in workers)


def test_implicit_difference_scales_with_the_solver_tolerance():
    """At the default tolerance (1e-6) the 3-rank positions agree with the serial ones to within 10×
    that tolerance (measured: 2.5e-6), and they move closer as the tolerance is tightened: the solve
    over ranks converges to the serial solution, not to a nearby one."""
    loose = ('--integration', 'implicit', '--viscosity', '1.0', '--speed', '0.3')
    tight = loose + ('--tolerance', '1e-12')
    d_loose = max_relative_position_difference(run_case(1, *loose)[0]['positions'], run_case(3, *loose)[0]['positions'])
    d_tight = max_relative_position_difference(run_case(1, *tight)[0]['positions'], run_case(3, *tight)[0]['positions'])
    assert d_loose <= 10 * yw.ViscBridgeImplicitSolver().tolerance
    assert d_tight < 0.01 * d_loose


@pytest.mark.parametrize('guard', [True, False])
def test_dt_differing_between_ranks_is_refused(guard):
    """Rank 1 given twice the dt between two runs: the guard (every step) or, without it, the time
    stepper (every update) stops every rank at once with a message naming the ranks and their dt."""
    options = ('--mismatch', '--steps', '20') + (() if guard else ('--no-guard',))
    results = run_case(3, *options)
    engine = 'ViscBridgeGuard' if guard else 'ViscBridgeTimeStepper'
    dts = results[0]['dts']
    for r in results:
        assert r['error'] is not None and engine + ': O.dt differs between the ranks of yade.mpy at step 5' in r['error']
        assert r['error'] == results[0]['error']  # the same stop everywhere
        assert r['iter'] == 5  # not one step with the wrong dt
    message = results[0]['error']
    assert 'rank 1: dt = %.10g s' % (2 * dts[-1]) in message and 'rank 2: dt = %.10g s' % dts[-1] in message


def test_guard_stop_is_global_and_names_rank_and_body():
    """An explicit dt 20 × above the viscous limit: the guard stops every rank at the step where the
    serial guard stops, with the serial diagnosis (energy sums, body, its bridge, a safe dt),
    prefixed with the rank that owns the body."""
    serial, parallel = run_case(1, '--dt', '5e-5'), run_case(3, '--dt', '5e-5')
    expected = serial[0]['error']
    assert expected and 'ViscBridgeGuard stopped the run at step' in expected and 'Body #' in expected
    for r in parallel:
        assert r['iter'] == serial[0]['iter']
        assert r['error'] == parallel[0]['error']
    prefix, _, rest = parallel[0]['error'].partition(') ')
    assert prefix.startswith('RuntimeError: (yade.mpy rank ') and prefix.endswith(' of 3')
    assert 'RuntimeError: ' + rest == expected
    assert int(prefix.split('rank ')[1].split()[0]) in (1, 2)  # a worker: the master owns no particle


def run_case_stopping_at_the_first_step(ranks, *options, timeout=60, case=CASE):
    """run_case for a run that every rank must stop at its first step (2–3 s), without a retry.
    YADE's O.run(n, True) can return normally on one rank after its engine raised (its wait() misses
    an error thrown before it first polls); that rank used to go on into mpirun's merge and wait for
    the others for ever, in about 1 run in 10. viscbridge.mpi now makes it raise instead."""
    return run_case(ranks, *options, timeout=timeout, case=case)


def test_particles_left_to_the_master_are_refused():
    """Without subdomains assigned, mpy leaves every particle to the master, which sends no states
    to the workers: the first step stops on every rank, naming a body and what to do — 20 times in
    a row, none hanging."""
    for attempt in range(20):
        _cache.clear()
        results = run_case_stopping_at_the_first_step(2, '--no-decompose', '--steps', '20')
        for r in results:
            assert r['iter'] == 0 and r['error'] == results[0]['error'], (attempt, results)
        assert results[0]['error'].startswith('RuntimeError: (yade.mpy rank 0 of 2) Body #')  # O.run reports any error so
        assert 'viscbridge.mpi.decompose()' in results[0]['error']


@pytest.mark.parametrize('integration', ['explicit', 'implicit'])
def test_a_clump_is_refused_on_every_rank(integration):
    """mpy has no notion of a clump: a scene with one stops at its first step on every rank, saying
    so and what to do — 5 times in a row, none hanging (serially, both schemes take clumps:
    tests/yade/test_clumps_implicit.py)."""
    for attempt in range(5):
        _cache.clear()
        results = run_case_stopping_at_the_first_step(2, '--clump', '--integration', integration, '--steps', '20')
        for r in results:
            assert r['iter'] == 0 and r['error'] == results[0]['error'], (attempt, results)
        assert 'is a clump, and yade.mpy distributes bodies one by one' in results[0]['error']
        assert 'in one process' in results[0]['error']


@pytest.mark.parametrize('how', ['engine', 'velocity'])
def test_a_moving_wall_moves_on_every_rank_as_serially(how):
    """A wall a TranslationEngine drives, or one given a velocity, stays with the master; the
    ViscBridgeBoundaryMotion that decompose() adds moves the workers' copies with it, so the run on
    3 ranks lands where the serial one does (the explicit case's rounding, as without the wall)."""
    serial = run_case(1, '--moving-wall', how)[0]
    split = run_case(3, '--moving-wall', how)
    assert serial['error'] is None and all(r['error'] is None for r in split), split
    worst = max(abs(a - b) for i, p in serial['positions'].items() for a, b in zip(p, split[0]['positions'][i]))
    assert worst < 1e-12, worst  # [m]; spheres of 0.2 mm


@pytest.mark.parametrize('how', ['engine', 'velocity'])
def test_a_moving_wall_without_boundary_motion_is_refused_on_every_rank(how):
    """Without ViscBridgeBoundaryMotion (a scene decomposed by hand or by mpy itself), mpy moves the
    master's bodies on the master only: the wall would stand still for the workers' particles — a
    different answer without an error.  The first step stops on every rank, naming the body and the
    engine to add — 3 times in a row, none hanging."""
    for attempt in range(3):
        _cache.clear()
        results = run_case_stopping_at_the_first_step(2, '--moving-wall', how, '--no-boundary-motion', '--steps', '20')
        for r in results:
            assert r['iter'] == 0 and r['error'] == results[0]['error'], (attempt, results)
        assert 'is a boundary that moves' in results[0]['error']
        assert ('driven by a TranslationEngine' if how == 'engine' else 'its velocity is set') in results[0]['error']
        assert 'viscbridge.mpi.decompose() adds the engine' in results[0]['error']


@pytest.mark.parametrize('options, refused', [
    (('--integration', 'implicit', '--accuracy', '1e-2'), 'ViscBridgeTimeStepper.accuracy=0.01 is not available under yade.mpy'),
    (('--integration', 'auto'), 'ViscBridgeTimeStepper.autoIntegration=True is not available under yade.mpy')])
def test_accuracy_and_the_automatic_scheme_are_refused_on_every_rank(options, refused):
    """The error estimate's carried parts do not cross the ranks (it would be smaller than serially,
    the step larger, without a word), and the choice of scheme rests on it: both stop the first step
    on every rank, saying what is allowed instead — 3 times in a row, none hanging."""
    for attempt in range(3):
        _cache.clear()
        results = run_case_stopping_at_the_first_step(3, *options, '--steps', '20')
        for r in results:
            assert r['error'] and refused in r['error'] and 'allowed there' in r['error'], (attempt, r)
            assert r['iter'] <= 1


def test_film_liquid_through_formation_and_rupture_across_ranks_is_the_serial_one():
    """The thrown spheres with films (1 % of each sphere's volume; explicit, 300 steps): bridges form
    from the films and rupture as the spheres bounce apart, some of them between the two workers'
    spheres.  On 3 ranks the scene keeps its liquid to 1e-12 and ends with the serial run's films
    (to 1e-12 of a film; the explicit runs differ by rounding), and the bridges formed and ruptured,
    summed over the ranks, are the serial counts."""
    serial = run_case(1, '--film')[0]
    split = run_case(3, '--film')
    assert serial['error'] is None and all(r['error'] is None for r in split), [r['error'] for r in split]
    formed, ruptured = serial['filmEvents']
    assert formed > 20 and ruptured > 5, serial['filmEvents']
    assert all(r['filmEvents'] == serial['filmEvents'] for r in split), [r['filmEvents'] for r in split]
    total = serial['initialLiquid']
    for result in (serial, split[0]):
        assert abs(sum(result['liquid']) - total) <= 1e-12 * total, (result['liquid'], total)
    films = serial['films']
    assert max(abs(films[k] - split[0]['films'][k]) for k in films) <= 1e-12 * max(films.values())
    assert split[0]['crossBridges'] > 0


def test_a_wettable_sphere_left_to_the_master_is_refused_with_film_liquid():
    """The master computes no interaction, so the film of a sphere it keeps (a fixed one) could not
    take part in the workers' bridges: the first step stops on every rank, naming the body and how
    to make it dry — 3 times in a row, none hanging."""
    for attempt in range(3):
        _cache.clear()
        results = run_case_stopping_at_the_first_step(3, '--film', '--fixed-sphere', '--steps', '20')
        for r in results:
            assert r['error'] and 'the master keeps' in r['error'] and 'is wettable' in r['error'], (attempt, r)
            assert 'viscbridge.liquid.make_dry(ids=[' in r['error'] and r['iter'] <= 1


def test_the_scenes_measures_of_a_split_scene_are_the_whole_scenes():
    """While the scene is split (after mp.mpirun without merging), a rank holds only its share of the
    bodies and interactions.  viscbridge.agglomerates() gathers the whole scene's on every rank: the
    same ids, labels and coordination as rank 0 finds on the merged scene at the same step, with
    bridges between the two workers' spheres; so do the liquid's totals and distribution (each bridge
    between two workers counted once).  write_particles writes one piece per rank, which hold every
    sphere once (the master's none)."""
    results = run_case(3, '--measure-split', '--steps', '150')
    assert [r['rank'] for r in results] == [0, 1, 2]
    merged = results[0]['mergedAgglomerates']
    assert len(merged['ids']) == 40 and merged['sizes'][0] >= 3 and merged['coordination'] > 0
    assert results[0]['crossBridges'] > 0
    for r in results:
        assert r['error'] is None, r
        assert r['splitAgglomerates'] == merged, r['rank']
        total, in_bridges, ids, per_sphere = r['splitLiquid']
        assert in_bridges > 0 and math.isclose(total, results[0]['mergedLiquid'][0], rel_tol=1e-14), (r['rank'], total)
        assert ids == results[0]['mergedLiquid'][2] and len(ids) == 40
        assert max(abs(a - b) for a, b in zip(per_sphere, results[0]['mergedLiquid'][3])) <= 1e-14 * total
        assert r['vtkPiece'][1], r['rank']  # the rank's own piece of the particles file
    assert [r['vtkPiece'][0] for r in results][0] == 0 and sum(r['vtkPiece'][0] for r in results) == 40


def test_an_agglomerate_history_over_the_ranks_is_the_serial_one():
    """An AgglomerateHistory recorder in every rank's engines: the rows (agglomerates, largest,
    coordination every 50 steps) are the serial run's on every rank, and rank 0 alone writes the CSV,
    one line per row."""
    serial = run_case(1, '--history')[0]
    rows = serial['historyRows']
    assert len(rows) >= 6 and rows[-1][1] < rows[0][1]  # bridges formed agglomerates
    for r in run_case(3, '--history'):
        assert r['error'] is None and r['historyRows'] == rows, r['rank']
    assert run_case(3, '--history')[0]['historyCsvLines'] == len(rows) + 1


def test_merged_scene_saved_and_run_on_serially(tmp_path):
    """150 steps on 3 ranks, merged and saved; loaded in one process the scene is refused (its
    particles belong to subdomains 1 and 2, which YADE's NewtonIntegrator would never move) until
    viscbridge.mpi.to_serial(), which also restarts the time stepper's mode iteration (the merged
    scene holds one rank's part of it); then 150 more steps follow the 300 serial steps with the dt
    of a fresh estimate (within 1 % of the serial run's warm-started one, whose residual correction
    differs) and land on positions within 1e-3."""
    saved = str(tmp_path / 'merged.yade.gz')
    first = run_case(3, '--steps', '150', '--save', saved)
    assert first[0]['error'] is None and os.path.exists(saved)
    resumed = run_case(1, '--load', saved, '--steps', '150')[0]
    assert 'NewtonIntegrator would never move it' in resumed['refusedBeforeToSerial']
    assert resumed['toSerial'] == 40 and resumed['error'] is None and resumed['iter'] == 300
    serial = run_case(1)[0]
    assert max(abs(a - b) / a for a, b in zip(serial['dts'][150:170], resumed['dts'])) <= 0.01
    assert max_relative_position_difference(serial['positions'], resumed['positions']) <= 1e-3
    assert energy_imbalance(resumed) <= 0.01


LONG_MPI_RUN = '''
from yade import mpy as mp
import viscbridge.mpi
import viscbridge.scenes as scenes
scenes.settling(n=20, viscosity=0.1)
viscbridge.mpi.decompose()
if mp.rank == 0:
    print('running', flush=True)
mp.mpirun(10**9, mp.numThreads)
print('the run finished', flush=True)
'''


@pytest.mark.parametrize('sig', [signal.SIGINT, signal.SIGTERM])
def test_a_signal_stops_every_rank(tmp_path, sig):
    """`./yadew mpirun` runs mpiexec under yadew's supervision: Ctrl-C (SIGINT) or SIGTERM ends the
    run on every rank, and no rank outlives it."""
    from test_stop import supervised, wait_for_line, wait_gone, processes_with
    import uuid
    script = tmp_path / 'long_mpi_run.py'
    script.write_text(LONG_MPI_RUN)
    token = uuid.uuid4().hex
    proc = supervised(['env', 'TMPDIR=' + str(tmp_path)] + MPIEXEC + ['-n', '3', 'yade', '-n', '-x', str(script), token], token)
    wait_for_line(proc, 'running')
    time.sleep(3)  # well inside mp.mpirun
    assert len(processes_with(token)) >= 3  # the ranks run
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=120)
    assert 'the run finished' not in out
    assert proc.returncode != 0
    assert wait_gone(token, 15), processes_with(token)
