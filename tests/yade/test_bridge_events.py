"""Bridge events (docs/architecture.md, "Channels"): the law publishes every formation and rupture
into the scene's ViscBridgeContext; an engine after the interaction loop (here the test engine
ViscBridgeEventCounter, which knows no other engine) reads them in (id1, id2) order, and what they
say agrees with the interactions."""
import pytest
from yade import O
import yade.wrapper as yw

import viscbridge.scenes as scenes
import pairscene


def test_every_pair_forms_and_ruptures_its_bridge_once():
    events = pairscene.build(pairs=40)
    O.run(20000, True)
    assert events.formed == 40 and events.ruptured == 40, 'each pair touched once and separated'
    assert events.mismatches == 0 and events.outOfOrder == 0
    assert pairscene.live_bridges() == []
    # the volume that left with the ruptured bridges is the volume the formed ones had
    assert events.volumeRuptured == pytest.approx(events.volumeFormed, rel=1e-14)
    assert events.volumeFormed == pytest.approx(40 * 0.01 * 4 / 3 * 3.141592653589793 * pairscene.R ** 3, rel=1e-12)


def test_events_count_the_live_bridges_of_a_settling_bed():
    # spheres thrown into each other and the walls: bridges form and rupture, with walls and at a distance
    scenes.settling(n=40, viscosity=0.01, seed=3, initialSpeed=0.3, cloudFraction=0.25, formationDistance=2.5e-4, width=5e-3)
    events = yw.ViscBridgeEventCounter()
    loop = next(i for i, e in enumerate(O.engines) if isinstance(e, yw.InteractionLoop))
    O.engines = O.engines[:loop + 1] + [events] + O.engines[loop + 1:]
    O.run(3000, True)
    live = [i for i in O.interactions if i.isReal and i.phys.bridge]
    assert events.formed > 40 and events.ruptured > 0
    assert events.formed - events.ruptured == len(live)
    assert events.mismatches == 0 and events.outOfOrder == 0
    assert events.volumeFormed - events.volumeRuptured == pytest.approx(sum(i.phys.bridgeVolume for i in live), rel=1e-12)


def test_the_context_lives_in_the_scene_and_is_not_needed_in_a_saved_one(tmp_path):
    pairscene.build(pairs=2, counter=False)
    O.run(10, True)
    assert sum(isinstance(p, yw.ViscBridgeContext) for p in O.miscParams) == 1
    path = str(tmp_path / 'scene.yade.gz')
    O.save(path)
    O.load(path)
    O.run(10, True)  # a loaded scene makes (or reuses) its context and runs on
    assert sum(isinstance(p, yw.ViscBridgeContext) for p in O.miscParams) == 1
