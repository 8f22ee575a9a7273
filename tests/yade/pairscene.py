"""A scene of separate pairs of wet spheres, for tests of bridge events: pair k's second sphere is
thrown at its partner, a bridge forms at contact, the pair rebounds and, with a thin liquid, the
bridge ruptures.  Each body has one interaction only, so its force sum has one term and the run is
the same on any number of threads (YADE's sums over several interactions are not)."""
from yade import O, utils
import yade.wrapper as yw

import viscbridge

R = 0.5e-3


def build(pairs=40, viscosity=0.0005, dt=2e-7, counter=True):
    """Pairs on a grid 10 r apart, approach speeds 0.1-0.3 m/s (all differ), no gravity; returns
    the event counter (the test engine ViscBridgeEventCounter) or None."""
    O.reset()
    mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, frictionAngle=0.5, density=2500))
    for k in range(pairs):
        x, y = 10 * R * (k % 8), 10 * R * (k // 8)
        O.bodies.append(utils.sphere((x, y, 0), R, material=mat))
        b = O.bodies[O.bodies.append(utils.sphere((x, y, 2.2 * R), R, material=mat))]
        b.state.vel = (0, 0, -(0.1 + 0.2 * k / pairs))
    O.engines = viscbridge.engines(gravity=(0, 0, 0), viscosity=viscosity, timeStepper=False, tangentialModel='slip')
    O.dt = dt
    if not counter:
        return None
    events = yw.ViscBridgeEventCounter()
    loop = next(i for i, e in enumerate(O.engines) if isinstance(e, yw.InteractionLoop))
    O.engines = O.engines[:loop + 1] + [events] + O.engines[loop + 1:]
    return events


def live_bridges():
    return [i for i in O.interactions if i.isReal and i.phys.bridge]
