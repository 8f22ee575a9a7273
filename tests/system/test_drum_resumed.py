"""A drum saved mid-run goes on in a new process: Drum.current() gives its handle back (a user had to
count steps for O.run, and could not spray it), with the parameters it was built and sprayed with."""
from yadeproc import run_yade

DRUM = '''
from viscbridge import scenes
R = 0.5e-3
'''

SAVE = DRUM + '''
import json, os, sys
from yade import O
d = scenes.drum(radius=R, drumRadius=10 * R, length=6 * R, n=40, viscosity=1.0, wetFraction=0.0)
d.spray(volumeRel=0.01, revolutions=0.2)
d.run(revolutions=0.05)
O.save(sys.argv[1])
json.dump(dict(params=d.params, period=d.period, spheres=d.spheres, facets=d.facets), open(os.environ['VISCBRIDGE_RESULT'], 'w'))
'''

LOAD = DRUM + '''
import json, os, sys
from yade import O
import viscbridge.liquid as liquid
O.load(sys.argv[1])
d = scenes.Drum.current()
d.run(revolutions=0.05)
json.dump(dict(params=d.params, period=d.period, spheres=d.spheres, facets=d.facets, revolutions=d.revolutions(),
               sprayed=liquid.sprayed()), open(os.environ['VISCBRIDGE_RESULT'], 'w'))
'''


def test_a_saved_drum_gives_its_handle_back_after_loading(tmp_path):
    saved = str(tmp_path / 'drum.yade.gz')
    _, built = run_yade(SAVE, saved)
    _, loaded = run_yade(LOAD, saved)
    assert loaded['params'] == built['params'] and loaded['params']['sprayRel'] == 0.01
    assert (loaded['period'], loaded['spheres'], loaded['facets']) == (built['period'], built['spheres'], built['facets'])
    assert abs(loaded['revolutions'] - 0.1) < 0.01  # turned on from where it was saved
    assert loaded['sprayed'] > 0


def test_without_a_drum_in_o_current_says_so():
    proc, _ = run_yade(DRUM + 'scenes.Drum.current()\n', check=False)
    assert proc.returncode != 0 and 'Drum.current: O holds no drum made by viscbridge.scenes.drum' in proc.stdout + proc.stderr
