"""The same run on 1 and 2 OpenMP threads (separate yade processes).

Explicit: equal up to rounding.  YADE's InteractionLoop hands the interactions to its threads with a
guided (dynamic) schedule and sums each thread's forces separately, so even two runs on 2 threads
differ in the last bits (1e-18 m/s between two such runs, measured); 3000 steps of contact dynamics
amplify that to relative differences of up to 5e-11 in the velocities and 9e-14 in the positions
(7 repeated runs): bounds 1e-8 and 1e-11.  A race or a contribution lost on one thread count would
differ by orders of magnitude more.  Implicit: the runs differ at the solver's level — YADE sums contact
forces per thread (rounding differences of ~1e-16), the implicit system amplifies them by its
condition number (Δt·C/m up to ~1e6), and CG may then stop one iteration apart: the velocities agree
to the CG tolerance (default 1e-6) times a safety factor of 100, the positions (which move by Δt·v
per step) to 1e-3 of it (measured: 1.2e-7 and 6.4e-11 at the default)."""
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


def relative(a, b, columns):
    worst = 0.0
    for ra, rb in zip(a, b):
        scale = max(max(abs(rb[c]) for c in columns), 1e-300)
        worst = max(worst, max(abs(ra[c] - rb[c]) for c in columns) / scale)
    return worst


TOLERANCE = yw.ViscBridgeImplicitSolver().tolerance  # the default the runs use


@pytest.mark.parametrize('integration,dt,steps,position_bound,velocity_bound', [
    ('explicit', 5e-9, 3000, 1e-11, 1e-8),
    ('implicit', 5e-6, 1000, 1e-3 * TOLERANCE, 100 * TOLERANCE),
])
def test_one_and_two_threads_agree(bed, integration, dt, steps, position_bound, velocity_bound):
    runs = [run_yade(SCRIPT, integration, dt, steps, bed, threads=t)[1] for t in (1, 2)]
    assert [r['threads'] for r in runs] == [1, 2]
    assert runs[0]['bridges'] == runs[1]['bridges'] > 50
    a, b = runs[0]['state'], runs[1]['state']
    pos, vel = relative(a, b, range(3)), relative(a, b, range(3, 9))
    print('%s: positions %.2g, velocities %.2g (relative)' % (integration, pos, vel))
    assert pos <= position_bound
    assert vel <= velocity_bound


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
