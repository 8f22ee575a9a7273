"""A spray saved with its scene continues in a new process (issue: the PyRunner of a spray failed
with a bare IndexError after O.load, and one re-created as the docs said sprayed again from t = 0)."""
import os

from wetbed import BED
from yadeproc import run_yade

SAVE = BED + '''
O.engines += [liquid.spray(rate=1e-9, box=((-R, -R, -R), (7 * R, 7 * R, 7 * R)), end=1e-2, iterPeriod=10, label='nozzle')]
O.run(150, True)
O.save(sys.argv[1])
O.run(400, True)
json.dump(dict(total=liquid.total(), sprayed=liquid.sprays()[0].sprayed, time=O.time), open(os.environ['VISCBRIDGE_RESULT'], 'w'))
'''

LOAD = '''
import json, os, sys
from yade import O
import viscbridge.liquid as liquid
O.load(sys.argv[1])
before = liquid.sprays()[0].sprayed
O.run(400, True)
json.dump(dict(total=liquid.total(), sprayed=liquid.sprays()[0].sprayed, before=before, time=O.time,
               label=liquid.sprays()[0].label), open(os.environ['VISCBRIDGE_RESULT'], 'w'))
'''


def test_a_saved_spray_continues_in_a_new_process(tmp_path):
    saved = str(tmp_path / 'sprayed.xml.bz2')
    _, straight = run_yade(SAVE, saved)
    assert os.path.exists(saved)
    _, resumed = run_yade(LOAD, saved)
    assert resumed['label'] == 'nozzle' and 0 < resumed['before'] < straight['sprayed']
    assert resumed['time'] == straight['time']
    assert abs(resumed['sprayed'] - straight['sprayed']) <= 1e-12 * straight['sprayed']  # nothing sprayed twice
    assert abs(resumed['total'] - straight['total']) <= 1e-12 * straight['total']
