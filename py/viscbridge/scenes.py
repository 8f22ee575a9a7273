"""Ready-made scenes: particles settling under gravity through viscous liquid bridges.

    import viscbridge.scenes as scenes
    s = scenes.settling(n=300, viscosity=1.0)      # builds the scene in O
    s.run(duration=0.01)
    print(s.kinetic_energy(), s.released_energy(), s.unstable())
    csv, png = s.save('settling')                     # the logged history

The history (time, kinetic energy, released potential energy, O.energy terms, bridges, time step)
is logged with yade.plot, so ``yade.plot.plots`` and the F8 plot window work as usual.
"""
import csv
import math
import os

from yade import O, plot, utils
from yade import pack
import yade.wrapper as yw

from . import criteria
from .engine_list import engines, bridge_parameters

__all__ = ['settling', 'Settling', 'instability']


def instability(kinetic, released, initial_kinetic=0.0):
    """Why a settling run is unstable, or None if it is not.

    The stated criterion: the kinetic energy of a run under gravity can only come from the released
    potential energy (plus what it had at the start); an explicit scheme above its stable step
    injects energy, so KE > KE₀ + released means the integration has blown up.  A NaN or inf in
    either number counts as unstable too.
    """
    if not (math.isfinite(kinetic) and math.isfinite(released)):
        return 'non-finite energy (kinetic=%r, released=%r)' % (kinetic, released)
    if kinetic > initial_kinetic + max(released, 0.0):
        return 'kinetic energy %.4g J exceeds the released potential energy %.4g J (+ initial %.4g J)' % (
            kinetic, released, initial_kinetic)
    return None


class Settling:
    """A settling scene living in O; see :func:`settling`."""

    def __init__(self, params, walls, heights):
        self.params = params
        self.walls = walls
        self._z0 = heights              # initial height of every dynamic body
        self.initial_kinetic = utils.kineticEnergy()
        self._recorder = None

    # -- measures -------------------------------------------------------------------------------
    def released_energy(self):
        """Potential energy released since the start: Σ m g (z₀ − z) [J]."""
        g = self.params['gravity']
        return sum(O.bodies[i].state.mass * g * (z0 - O.bodies[i].state.pos[2]) for i, z0 in self._z0.items())

    def kinetic_energy(self):
        """Translational + rotational kinetic energy of all bodies [J]."""
        return utils.kineticEnergy()

    def bridges(self):
        """Number of interactions with a liquid bridge."""
        return sum(1 for i in O.interactions if i.isReal and getattr(i.phys, 'bridge', False))

    def unstable(self):
        """The instability criterion (:func:`instability`) applied now; None while stable."""
        return instability(self.kinetic_energy(), self.released_energy(), self.initial_kinetic)

    # -- running --------------------------------------------------------------------------------
    def record(self):
        """Append one row to yade.plot.data (called by the scene's PyRunner)."""
        row = dict(t=O.time, iter=O.iter, dt=O.dt, Ek=self.kinetic_energy(), Ereleased=self.released_energy(),
                   bridges=self.bridges())
        if O.trackEnergy:
            row.update(('E_' + k, v) for k, v in O.energy.items())
            row['Etotal'] = O.energy.total()
        plot.addData(**row)

    def run(self, duration=None, steps=None, points=200, stop_when_unstable=True):
        """Advance the scene by `duration` [s] of simulated time or by `steps` steps, logging about
        `points` rows; with stop_when_unstable, stop at the first logged row that fails the
        instability criterion (:func:`instability`).  Returns why it stopped early, or None."""
        if (duration is None) == (steps is None):
            raise ValueError('Settling.run: give exactly one of duration=... [s] or steps=...')
        if duration is not None and not duration > 0:
            raise ValueError('Settling.run: duration=%r is out of range; allowed: > 0 [s]' % (duration,))
        if steps is not None and not (int(steps) == steps and steps > 0):
            raise ValueError('Settling.run: steps=%r is out of range; allowed: integer > 0' % (steps,))
        if not (isinstance(points, int) and points >= 1):
            raise ValueError('Settling.run: points=%r is out of range; allowed: integer >= 1' % (points,))
        if not plot.data:
            self.record()
        self.stopped_because = None
        self._stop_when_unstable = stop_when_unstable
        # One O.run() for the whole stretch (O.run(n, True) polls every 40 ms, so many short runs
        # would be slow); a PyRunner logs, checks stability and pauses the run when it fails.
        if steps is not None:
            logger = yw.PyRunner(iterPeriod=max(1, int(steps) // points), command=_LOG_COMMAND)
        else:
            logger = yw.PyRunner(virtPeriod=duration / points, command=_LOG_COMMAND)
        _ACTIVE[0] = self
        O.engines = O.engines + [logger]
        try:
            if steps is not None:
                O.run(int(steps), True)
            else:
                O.stopAtTime = O.time + duration
                O.run(-1, True)
                O.stopAtTime = 0
        finally:
            O.engines = [e for e in O.engines if not (isinstance(e, yw.PyRunner) and e.command == _LOG_COMMAND)]
            _ACTIVE[0] = None
        if self.stopped_because is None:
            self.record()
        return self.stopped_because

    def _log(self):
        self.record()
        why = self.unstable()
        if why and self._stop_when_unstable and self.stopped_because is None:
            self.stopped_because = why
            O.pause()

    # -- output ---------------------------------------------------------------------------------
    def save(self, prefix):
        """Write the logged history to ``prefix.csv`` and a plot to ``prefix.png``; return both paths.
        Directories are created; nothing already logged is dropped."""
        directory = os.path.dirname(os.path.abspath(prefix))
        os.makedirs(directory, exist_ok=True)
        csv_path, png_path = prefix + '.csv', prefix + '.png'
        write_history_csv(plot.data, csv_path)
        plot_history(plot.data, png_path, title=self.describe())
        return csv_path, png_path

    def describe(self):
        p = self.params
        dt = ('dt %.3g s' % p['dt']) if p['dt'] else 'stepper (safety %s)' % (p['safety'] if p['safety'] else 'default')
        return 'n=%d, r=%.3g m, μ=%.3g Pa·s, S_min/r̄=%s, %s, %s' % (
            p['n'], p['radius'], p['viscosity'], p['sMinRel'] if not p['sMin'] else '%.3g m' % p['sMin'],
            p['integration'], dt)


_ACTIVE = [None]
_LOG_COMMAND = 'import viscbridge.scenes; viscbridge.scenes._log()'


def _log():
    """PyRunner hook of :meth:`Settling.run`."""
    if _ACTIVE[0] is not None:
        _ACTIVE[0]._log()


def write_history_csv(data, path):
    """yade.plot.data (dict of equal-length columns) as CSV with a header row."""
    keys = sorted(data, key=lambda k: (k not in ('t', 'iter', 'dt'), k))
    rows = zip(*(data[k] for k in keys))
    tmp = path + '.part'
    with open(tmp, 'w', newline='') as fh:
        w = csv.writer(fh)
        w.writerow(keys)
        w.writerows(rows)
    os.replace(tmp, path)


def plot_history(data, path, title=''):
    """Kinetic and released potential energy against time (log scale)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.2))
    t = data.get('t', [])
    for key, label in (('Ek', 'kinetic energy'), ('Ereleased', 'released potential energy')):
        ys = [max(v, 1e-300) for v in data.get(key, [])]
        if ys:
            ax.semilogy(t, ys, label=label)
    ax.set_xlabel('time [s]')
    ax.set_ylabel('energy [J]')
    ax.set_title(title, fontsize=9)
    ax.legend()
    ax.grid(True, which='both', alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _positive(name, value, unit=''):
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise ValueError('settling: %s=%r is out of range; allowed: > 0%s' % (name, value, unit))


def settling(n=300, radius=0.5e-3, sizeRatio=1.0, density=2500.0, young=1e7, poisson=0.3, friction=0.5,
             viscosity=1.0, dt=None, safety=None, seed=1, width=None, height=None, periodic=False,
             gravity=9.81, initialSpeed=0.0, integration='explicit', trackEnergy=True, guard=True,
             **effects):
    """Build a settling scene in O (which is reset) and return a :class:`Settling` handle.

    n spheres of mean radius `radius` [m] (radii uniform in a range with max/min = sizeRatio, 1–5)
    are placed at random, without contact, in a column of square cross-section `width` (default
    10 mean diameters) and height `height` (default: a loose packing of solid fraction 0.2), above a
    floor.  The sides are walls, or periodic with periodic=True.  They settle under `gravity`
    [m/s²] through liquid of `viscosity` [Pa·s]; the other liquid and model parameters
    (sMin/sMinRel, bridgeVolume/bridgeVolumeRel, contactAngle, normalModel, tangentialModel,
    formationDistance, en) are those of :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys`.

    dt: a fixed time step [s], or None for ViscBridgeTimeStepper with `safety` (None: its default).
    initialSpeed: random initial velocities of this magnitude [m/s] (to start with motion).
    seed: random seed of the positions (and velocities).
    """
    _positive('n', n)
    _positive('radius', radius, ' [m]')
    _positive('density', density, ' [kg/m³]')
    _positive('young', young, ' [Pa]')
    _positive('gravity', gravity, ' [m/s²]')
    if not (1.0 <= sizeRatio <= 5.0):
        raise ValueError('settling: sizeRatio=%r is out of range; allowed: [1, 5]' % (sizeRatio,))
    if not (-1.0 < poisson < 0.5):
        raise ValueError('settling: poisson=%r is out of range; allowed: (-1, 0.5)' % (poisson,))
    if not friction >= 0:
        raise ValueError('settling: friction=%r is out of range; allowed: >= 0 [rad]' % (friction,))
    if dt is not None:
        _positive('dt', dt, ' [s]')
    if safety is not None and not (0 < safety <= 1):
        raise ValueError('settling: safety=%r is out of range; allowed: (0, 1]' % (safety,))
    if initialSpeed < 0:
        raise ValueError('settling: initialSpeed=%r is out of range; allowed: >= 0 [m/s]' % (initialSpeed,))
    ip2_args, rest = bridge_parameters(viscosity=viscosity, **effects)
    if rest:
        raise ValueError('settling: unknown parameter(s) %s' % ', '.join(sorted(rest)))

    O.reset()
    plot.reset()
    fuzz = (sizeRatio - 1.0) / (sizeRatio + 1.0)
    r_min = radius * (1 - fuzz)
    width = width or 20 * radius
    mean_volume = 4.0 / 3.0 * math.pi * radius ** 3 * (1 + 3 * fuzz ** 2 / 3)
    height = height or max(n * mean_volume / (0.2 * width * width), 8 * radius)
    _positive('width', width, ' [m]')
    _positive('height', height, ' [m]')
    mat = O.materials.append(yw.FrictMat(young=young, poisson=poisson, density=density, frictionAngle=friction))

    sp = pack.SpherePack()
    lo, hi = (0, 0, 0), (width, width, height)
    if periodic:
        O.periodic = True
        O.cell.setBox(width, width, 4 * height)
        placed = sp.makeCloud(lo, hi, rMean=radius, rRelFuzz=fuzz, num=n, periodic=True, seed=seed)
    else:
        placed = sp.makeCloud(lo, hi, rMean=radius, rRelFuzz=fuzz, num=n, seed=seed)
    if placed < n:
        raise ValueError('settling: only %d of n=%d spheres fit in width=%g m × height=%g m; allowed: a larger '
                         'width or height' % (placed, n, width, height))
    walls = [O.bodies.append(utils.wall(0, axis=2, sense=1, material=mat))]
    if not periodic:
        walls += [O.bodies.append(utils.wall(p, axis=a, material=mat)) for a in (0, 1) for p in (0, width)]
    ids = sp.toSimulation(material=mat)
    if periodic:  # the cloud's own z range starts at 0; lift it above the floor
        for i in ids:
            O.bodies[i].state.pos += (0, 0, 1.01 * radius * (1 + fuzz))
    else:
        for i in ids:
            O.bodies[i].state.pos += (0, 0, 0.01 * radius)

    if initialSpeed > 0:
        import random
        rng = random.Random(seed)
        for i in ids:
            v = [rng.gauss(0, 1) for _ in range(3)]
            norm = math.sqrt(sum(x * x for x in v)) or 1.0
            O.bodies[i].state.vel = tuple(initialSpeed * x / norm for x in v)

    O.engines = engines(gravity=(0, 0, -gravity), integration=integration, timeStepper=dt is None, safety=safety,
                        guard=guard, minRadius=r_min, **ip2_args)
    if dt is None:
        # start from the collision bound: the stepper only lets dt grow gradually
        O.dt = 0.2 * criteria.rayleigh_time(r_min, density, young, poisson)
    else:
        O.dt = dt
    O.trackEnergy = trackEnergy
    params = dict(n=n, radius=radius, sizeRatio=sizeRatio, density=density, young=young, poisson=poisson,
                  friction=friction, dt=dt, safety=safety, seed=seed, width=width, height=height,
                  periodic=periodic, gravity=gravity, initialSpeed=initialSpeed, integration=integration,
                  sMin=0.0, sMinRel=1e-3)
    params.update(ip2_args)
    return Settling(params, walls, {i: O.bodies[i].state.pos[2] for i in ids})
