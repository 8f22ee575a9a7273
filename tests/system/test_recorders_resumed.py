"""The recorders of a saved scene go on in a new process: an AgglomerateHistory and a VTK series
saved with the scene (their ViscBridgeRecorders) append to the same CSV and collections after O.load
(their commands used to look the history or series up in a list of the process that made them: a
bare IndexError or KeyError at the first recorded step after loading)."""
import csv
import math
import os
import xml.etree.ElementTree as ET

from wetbed import BED
from yadeproc import run_yade

SAVE = BED + '''
liquid.set_film(range(1, 19), 0.02 * 4 / 3 * 3.14159 * R ** 3)
import viscbridge.vtk as vtk
from viscbridge.analysis.agglomerate_history import AgglomerateHistory
history = AgglomerateHistory('out/agglomerates.csv', period=1e-3)
O.engines = O.engines + [history.recorder(iterPeriod=50), vtk.bridge_recorder('out/vtk/', iterPeriod=100)]
O.run(200, True)
O.save(sys.argv[1])
'''

LOAD = '''
import json, os, sys
from yade import O
from viscbridge.analysis.agglomerate_history import AgglomerateHistory
O.load(sys.argv[1])
O.run(120, True)
history = AgglomerateHistory.resume('out/agglomerates.csv')
history.plot('out/agglomerates.png')
json.dump(dict(iter=O.iter, rows=len(history.rows)), open(os.environ['VISCBRIDGE_RESULT'], 'w'))
'''


def test_saved_recorders_go_on_after_loading_in_a_new_process(tmp_path):
    saved = str(tmp_path / 'scene.xml.bz2')
    run_yade(SAVE, saved, cwd=str(tmp_path))
    other = tmp_path / 'elsewhere'
    other.mkdir()
    # the loading process starts elsewhere: the recorders hold their files from the root
    _, loaded = run_yade(LOAD.replace("'out/", "'%s/out/" % tmp_path), saved, cwd=str(other))
    rows = list(csv.DictReader(open(tmp_path / 'out' / 'agglomerates.csv')))
    steps = [int(r['iter']) for r in rows]
    # rows at 0, 50, ..., 200 before saving; then every 50 steps and the run's last step (320)
    assert steps == [0, 50, 100, 150, 200, 250, 300, 320]
    assert loaded == dict(iter=320, rows=8)
    # the first transitions after loading are unknown (the agglomerates of the row before are not saved)
    assert [r['broken'] == 'nan' for r in rows] == [False] * 5 + [True] + [False] * 2
    assert [r['merged'] == 'nan' for r in rows] == [False] * 5 + [True] + [False] * 2
    assert all(math.isclose(float(r['revolutions']), float(r['t']) / 1e-3) for r in rows)  # the period kept
    frames = [int(d.get('file').split('.')[-2]) for d in ET.parse(tmp_path / 'out' / 'vtk' / 'bridges.pvd').iter('DataSet')]
    assert frames == [0, 100, 200, 300, 320]
    assert all((tmp_path / 'out' / 'vtk' / ('bridges.%010d.vtp' % f)).exists() for f in frames)
    assert (tmp_path / 'out' / 'agglomerates.png').stat().st_size > 10000


def test_a_recorder_whose_files_are_gone_says_what_to_do(tmp_path):
    saved = str(tmp_path / 'scene.xml.bz2')
    run_yade(SAVE, saved, cwd=str(tmp_path))
    os.remove(tmp_path / 'out' / 'agglomerates.json')
    proc, _ = run_yade(LOAD.replace("'out/", "'%s/out/" % tmp_path), saved, cwd=str(tmp_path), check=False)
    assert proc.returncode != 0
    assert 'agglomerates.json is not there' in proc.stdout + proc.stderr
    assert 'make a new AgglomerateHistory and recorder after O.load' in proc.stdout + proc.stderr


def test_a_run_branched_from_an_earlier_save_does_not_write_into_the_first_one(tmp_path):
    """Loading the same saved scene twice (a second continuation, or a copied run directory) appended
    the second branch's rows and frames to the first's files, time going backwards, without a word."""
    saved = str(tmp_path / 'scene.xml.bz2')
    run_yade(SAVE, saved, cwd=str(tmp_path))
    load = LOAD.replace("'out/", "'%s/out/" % tmp_path)
    run_yade(load, saved, cwd=str(tmp_path))
    before = (tmp_path / 'out' / 'agglomerates.csv').read_text(), (tmp_path / 'out' / 'vtk' / 'bridges.pvd').read_text()
    proc, _ = run_yade(load, saved, cwd=str(tmp_path), check=False)
    assert proc.returncode != 0
    assert 'has rows up to step 320, past this scene\'s step 250' in proc.stdout + proc.stderr
    assert 'make a new AgglomerateHistory(...) with another file' in proc.stdout + proc.stderr
    after = (tmp_path / 'out' / 'agglomerates.csv').read_text(), (tmp_path / 'out' / 'vtk' / 'bridges.pvd').read_text()
    assert after == before


def test_a_new_history_over_an_old_csv_says_it_replaces_its_rows(tmp_path):
    script = BED + """
import warnings
from viscbridge.analysis.agglomerate_history import AgglomerateHistory
AgglomerateHistory('a.csv').record()
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter('always')
    AgglomerateHistory('a.csv')
json.dump([str(w.message) for w in caught], open(os.environ['VISCBRIDGE_RESULT'], 'w'))
"""
    _, said = run_yade(script, cwd=str(tmp_path))
    assert said == ["AgglomerateHistory: a.csv had 1 row, now replaced by this new history "
                    "(AgglomerateHistory.resume('a.csv') would have gone on with them)"]
