"""The same run on 1 and 2 OpenMP threads (separate yade processes): bit-identical.

YADE's InteractionLoop hands the interactions to its threads with a guided (dynamic) schedule and
sums each thread's forces separately, and its collider inserts interactions in an order that depends
on the threads.  ViscBridgeForceSum (after the loop) adds the law's forces per body in the order of
the partners' ids, and every sum over the contacts that reaches the motion (time step, implicit
system, error estimate) runs in that order (OrderedWetContacts): the runs agree to the last bit.
Before, two runs on 2 threads differed by 1e-18 m/s after one step, and a film drum with dry
contacts grew that into a bed centre 0.1 mm apart within 8000 steps."""
import json

import pytest
import yade.wrapper as yw

from yadeproc import run_yade

SCRIPT = """
import json, os, sys
import viscbridge.scan as scan
from yade import O
case = scan.normalize_case(dict(n=200, viscosity=10.0, seed=8, integration=sys.argv[1]))
trial = scan._Trial(case, sys.argv[4])  # the wetted bed: every contact a bridge
trial.prepare()
O.dt = float(sys.argv[2])
O.run(int(sys.argv[3]), True)
json.dump({'threads': O.numThreads, 'bridges': sum(1 for i in O.interactions if i.isReal and i.phys.bridge),
           'state': [list(b.state.pos) + list(b.state.vel) + list(b.state.angVel) for b in O.bodies]},
          open(os.environ['VISCBRIDGE_RESULT'], 'w'))
"""


@pytest.fixture(scope='module')
def bed(tmp_path_factory):
    import viscbridge.scan as scan
    case = scan.normalize_case(dict(n=200, viscosity=10.0, seed=8))
    return scan.dry_bed(case, str(tmp_path_factory.mktemp('beds')))


@pytest.mark.parametrize('integration,dt,steps', [('explicit', 5e-9, 3000), ('implicit', 5e-6, 1000)])
def test_one_and_two_threads_agree(bed, integration, dt, steps):
    runs = [run_yade(SCRIPT, integration, dt, steps, bed, threads=t)[1] for t in (1, 2)]
    assert [r['threads'] for r in runs] == [1, 2]
    assert runs[0]['bridges'] == runs[1]['bridges'] > 50
    assert runs[0]['state'] == runs[1]['state']


EVENTS_SCRIPT = """
import json, os, sys
sys.path.insert(0, %r)
import pairscene
from yade import O
events = pairscene.build(pairs=64)
O.run(20000, True)
json.dump({'threads': O.numThreads, 'formed': events.formed, 'ruptured': events.ruptured, 'digest': events.digest,
           'mismatches': events.mismatches, 'outOfOrder': events.outOfOrder,
           'state': [list(b.state.pos) + list(b.state.vel) for b in O.bodies]}, open(os.environ['VISCBRIDGE_RESULT'], 'w'))
"""


def test_bridge_events_come_in_the_same_order_on_1_and_2_threads():
    # separate pairs (one interaction per body: the same run on any thread count), published from
    # whichever thread handles the pair, read in one order
    import os
    script = EVENTS_SCRIPT % os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'yade')
    _, one = run_yade(script, threads=1)
    _, two = run_yade(script, threads=2)
    assert (one['threads'], two['threads']) == (1, 2)
    assert one['state'] == two['state']
    assert one['formed'] == one['ruptured'] == 64
    for r in (one, two):
        assert r['mismatches'] == 0 and r['outOfOrder'] == 0
    assert one['digest'] == two['digest']


FILM_SCRIPT = """
import json, math, os
from yade import O, utils
import yade.wrapper as yw
import viscbridge, viscbridge.liquid as liquid
R = 0.5e-3
mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, frictionAngle=0.5, density=2500))
# 40 rows of five kinematic spheres (their motion is prescribed, so the run is the same on any
# number of threads and only the liquid can differ): the outer four close in on the middle one at
# speeds that differ from row to row, so many bodies get two bridges in one step
ids = []
for row in range(40):
    y = 10 * R * row
    for k in range(5):
        b = utils.sphere(((2.3 * R) * (k - 2), y, 0), R, material=mat)
        b.state.blockedDOFs = 'xyz'  # rotations free: a sphere with nothing free is no agglomerate member
        b.state.vel = (-(0.03 + 0.001 * row) * (k - 2), 0, 0)
        ids.append(O.bodies.append(b))
O.engines = viscbridge.engines(gravity=(0, 0, 0), timeStepper=False, viscosity=0.01, liquidModel='film', formationDistance=0.05 * R,
                               minBridgeVolume=float(os.environ.get('MIN_BRIDGE', 0)))
O.dt = 1e-6
liquid.set_film(ids, [(1 + (7 * i) % 5) * 1e-13 for i in ids])
total = liquid.total()
O.run(6000, True)
together = viscbridge.agglomerates()
for b in O.bodies:
    b.state.vel = -b.state.vel
O.run(12000, True)
engine = next(e for e in O.engines if isinstance(e, yw.ViscBridgeLiquid))
json.dump({'threads': O.numThreads, 'films': [liquid.film(i) for i in ids], 'formed': engine.formed, 'ruptured': engine.ruptured,
           'total': [total, liquid.total()], 'sizes': together.sizes.tolist(), 'labels': together.labels.tolist()},
          open(os.environ['VISCBRIDGE_RESULT'], 'w'))
"""


@pytest.mark.parametrize('min_bridge', [0, 6e-13])
def test_liquid_moves_identically_on_1_and_2_threads(min_bridge):
    """The offer rule L1 and the threshold L5 read the step's formations in one order (physics.md
    §11): the films after formations and ruptures, and the agglomerates of the bridges, are
    bit-identical on 1 and 2 threads, and the total is conserved."""
    env = {'MIN_BRIDGE': repr(min_bridge)}
    _, one = run_yade(FILM_SCRIPT, threads=1, env=env)
    _, two = run_yade(FILM_SCRIPT, threads=2, env=env)
    assert (one['threads'], two['threads']) == (1, 2)
    # 40 rows of five: without a threshold every row is one agglomerate of five; with it some
    # contacts stay dry (films of 1e-13 to 5e-13 m³, some shared among two bridges)
    if min_bridge:
        assert 40 < len(one['sizes']) < 200 and one['formed'] < 160
    else:
        assert one['sizes'] == [5] * 40 and one['formed'] >= 160
    assert one['ruptured'] == one['formed']
    assert one['films'] == two['films'] and one['formed'] == two['formed']
    assert one['sizes'] == two['sizes'] and one['labels'] == two['labels']
    for r in (one, two):
        assert abs(r['total'][1] - r['total'][0]) <= 1e-12 * r['total'][0]


DRUM_SCRIPT = """
import json, os, sys
from yade import O
import viscbridge, viscbridge.liquid as liquid
from viscbridge import scenes
accuracy = None if sys.argv[2] == 'none' else float(sys.argv[2])
scenes.drum(n=300, liquidModel='film', accuracy=accuracy)
total = liquid.total()
O.run(int(sys.argv[1]), True)
json.dump({'threads': O.numThreads, 'iter': O.iter, 'time': O.time, 'total': [total, liquid.total()],
           'bridges': sum(1 for i in O.interactions if i.isReal and i.phys.bridge),
           'state': [list(b.state.pos) + list(b.state.vel) + [liquid.film(b.id) if b.dynamic else 0] for b in O.bodies]},
          open(os.environ['VISCBRIDGE_RESULT'], 'w'))
"""


@pytest.mark.parametrize('steps,accuracy', [(3000, 'none'), (3000, '1e-2')])
def test_a_film_drum_is_bit_identical_on_1_and_2_threads_run_after_run(steps, accuracy):
    """The product's drum with film liquid (dry and wet contacts against turning facets): positions,
    velocities and films equal to the last bit on 1 thread and in two runs on 2 threads.  Before
    ViscBridgeForceSum and OrderedWetContacts the runs parted between steps 1500 and 1900."""
    one = run_yade(DRUM_SCRIPT, steps, accuracy, threads=1)[1]
    two = [run_yade(DRUM_SCRIPT, steps, accuracy, threads=2)[1] for _ in range(2)]
    assert [one['threads']] + [r['threads'] for r in two] == [1, 2, 2]
    assert one['bridges'] > 10  # a wet bed, not a cloud still falling
    for r in two:
        assert (r['iter'], r['time']) == (one['iter'], one['time'])
        assert r['state'] == one['state']
    assert abs(one['total'][1] - one['total'][0]) <= 1e-12 * one['total'][0]
