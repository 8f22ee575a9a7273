"""A step that threw is repeated by YADE with the same iter (Scene::moveToNextTimeStep advances it
only at the end of a step).  For ViscBridge the repeat is a new loop pass: the force sum adds the
repeat's forces, not the failed try's again as well (which crashed: its ordered list pointed into
queues the repeat had grown), and not twice (docs/architecture.md, "One YADE step").

YADE's incremental contact laws add their shear increment once more in a repeated step (the
positions did not move, so the increment is the same): the repeat is not the step without the
error, for YADE's own laws either.  The test compares the force sum with what the law adds itself."""
import pytest
from yade import O
import yade.wrapper as yw

import viscbridge.scenes as scenes

SNAPSHOT = 'import builtins; builtins.vb_forces = [(tuple(O.forces.f(b.id)), tuple(O.forces.t(b.id))) for b in O.bodies]'


def insert_after_force_sum(engine):
    at = next(k for k, e in enumerate(O.engines) if isinstance(e, yw.ViscBridgeForceSum)) + 1
    O.engines = O.engines[:at] + [engine] + O.engines[at:]


def forces_of_a_repeated_step(run_error, summed):
    """The forces on every body after the loop and the force sum of a step repeated after an error."""
    import builtins
    O.loadTmp('wet')
    insert_after_force_sum(yw.PyRunner(iterPeriod=1, command='raise ValueError("planted")', label='planted'))
    assert 'planted' in run_error(1) and O.iter == 300
    O.engines = [e for e in O.engines if e.label != 'planted']
    insert_after_force_sum(yw.PyRunner(iterPeriod=1, command=SNAPSHOT))
    next(e for e in O.engines if isinstance(e, yw.ViscBridgeForceSum)).dead = not summed
    O.step()
    assert O.iter == 301
    return builtins.vb_forces


@pytest.mark.parametrize('integration', ['explicit', 'implicit'])
def test_a_repeated_step_sums_the_forces_of_its_own_loop_pass_once(integration, run_error):
    scenes.settling(n=40, viscosity=10.0 if integration == 'implicit' else 0.1, seed=3, initialSpeed=0.3,
                    cloudFraction=0.25, width=5e-3, integration=integration)
    O.run(300, True)
    assert sum(1 for i in O.interactions if i.isReal and i.phys.bridge) >= 10
    O.saveTmp('wet')
    summed = forces_of_a_repeated_step(run_error, summed=True)
    own = forces_of_a_repeated_step(run_error, summed=False)
    loaded = [k for k, (f, t) in enumerate(own) if max(map(abs, f)) > 0]
    assert len(loaded) >= 10
    for (f, t), (f0, t0) in zip(summed, own):
        assert f == pytest.approx(f0, rel=1e-12, abs=1e-18) and t == pytest.approx(t0, rel=1e-12, abs=1e-21)
