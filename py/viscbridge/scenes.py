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

from . import _checks, criteria
from .engine_list import engines, bridge_parameters

__all__ = ['settling', 'Settling', 'instability', 'capillary_input']


def instability(kinetic, released, initial_kinetic=0.0):
    """Why a settling run is unstable, or None if it is not.

    The stated criterion: the kinetic energy of a run under gravity can only come from the released
    potential energy (plus what it had at the start); an explicit scheme above its stable step
    injects energy, so KE > KE₀ + released means the integration has blown up.  A NaN or inf in
    either number counts as unstable too.  With capillary forces, ``released`` must include what
    they have put in (:func:`capillary_input`): they pull the particles together by themselves.
    """
    if not (math.isfinite(kinetic) and math.isfinite(released)):
        return 'non-finite energy (kinetic=%r, released=%r)' % (kinetic, released)
    if kinetic > initial_kinetic + max(released, 0.0):
        return 'kinetic energy %.4g J exceeds the released potential energy %.4g J (+ initial %.4g J)' % (
            kinetic, released, initial_kinetic)
    return None


def capillary_input():
    """Energy the capillary forces have put into the particles [J] since the scene's ViscBridge law
    was created (its ``capillaryInput``, physics.md P21); 0 without capillary forces."""
    for loop in (e for e in O.engines if isinstance(e, yw.InteractionLoop)):
        for law in loop.lawDispatcher.functors:
            if isinstance(law, yw.Law2_ScGeom_ViscBridgePhys_HertzViscous):
                return law.capillaryInput
    return 0.0


class Settling:
    """A settling scene living in O; see :func:`settling`."""

    def __init__(self, params, walls, heights):
        self.params = params
        self.walls = walls
        self._z0 = heights              # initial height of every dynamic body
        self.initial_kinetic = utils.kineticEnergy()
        self._capillary0 = capillary_input()
        self.stopped_because = None
        self.stopped_at = None          # simulated time of the stop, if the run was stopped

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
        """The instability criterion (:func:`instability`) applied now, the capillary forces' input
        counted with the released potential energy; None while stable."""
        released = self.released_energy() + capillary_input() - self._capillary0
        return instability(self.kinetic_energy(), released, self.initial_kinetic)

    def guard(self):
        """The scene's ViscBridgeGuard, or None."""
        return next((e for e in O.engines if isinstance(e, yw.ViscBridgeGuard)), None)

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
        `points` rows.  Returns why it stopped early, or None: with stop_when_unstable, the first
        logged row that fails the instability criterion (:func:`instability`); and always a stop by
        the scene's ViscBridgeGuard, whose diagnosis (body, contact, criterion, safe Δt) is then the
        reason — a blow-up stopped is a result, not an error."""
        f = 'Settling.run'
        if (duration is None) == (steps is None):
            raise ValueError('Settling.run: give exactly one of duration=... [s] or steps=...')
        if duration is not None:
            _checks.positive(f, 'duration', duration, ' [s]')
        if steps is not None:
            steps = _checks.integer(f, 'steps', steps, minimum=1)
        points = _checks.integer(f, 'points', points, minimum=1)
        if not plot.data:
            self.record()
        self.stopped_because = self.stopped_at = None
        self._stop_when_unstable = stop_when_unstable
        # One O.run() for the whole stretch (O.run(n, True) polls every 40 ms, so many short runs
        # would be slow); a PyRunner logs, checks stability and pauses the run when it fails.
        if steps is not None:
            logger = yw.PyRunner(iterPeriod=max(1, steps // points), command=_LOG_COMMAND)
        else:
            logger = yw.PyRunner(virtPeriod=duration / points, command=_LOG_COMMAND)
        _ACTIVE[0] = self
        O.engines = O.engines + [logger]
        guard = self.guard()
        guard_error = guard.lastError if guard else ''
        try:
            self._run_and_wait(steps, duration)
        except RuntimeError:
            if not (guard and guard.lastError != guard_error):
                raise
        finally:
            O.engines = [e for e in O.engines if not (isinstance(e, yw.PyRunner) and e.command == _LOG_COMMAND)]
            _ACTIVE[0] = None
            O.stopAtTime = 0
        # YADE's O.wait() can miss an exception thrown in the very first steps: read the guard itself
        if guard and guard.lastError != guard_error and self.stopped_because is None:
            self.stopped_because = guard.lastError
            self.stopped_at = O.time
        self.record()
        return self.stopped_because

    @staticmethod
    def _run_and_wait(steps, duration):
        if steps is not None:
            O.run(steps, True)
        else:
            O.stopAtTime = O.time + duration
            O.run(-1, True)

    def settle(self, max_duration, rest_fraction=1e-3, chunks=40, stop_when_unstable=True):
        """Run until the particles come to rest — the kinetic energy below `rest_fraction` of its
        peak, after the peak — or for at most `max_duration` [s].  Returns (why it stopped early or
        None, whether it came to rest)."""
        f = 'Settling.settle'
        _checks.positive(f, 'max_duration', max_duration, ' [s]')
        _checks.in_range(f, 'rest_fraction', rest_fraction, 0, 1, lo_open=True, hi_open=True)
        chunks = _checks.integer(f, 'chunks', chunks, minimum=1)
        end, peak = O.time + max_duration, self.kinetic_energy()
        while O.time < end * (1 - 1e-12):
            why = self.run(duration=min(max_duration / chunks, end - O.time), points=max(1, 400 // chunks),
                           stop_when_unstable=stop_when_unstable)
            if why:
                return why, False
            ke = self.kinetic_energy()
            if ke < rest_fraction * peak and self.bridges() > 0:
                return None, True
            peak = max(peak, max(plot.data['Ek']))
        return None, False

    def _log(self):
        self.record()
        why = self.unstable()
        if why and self._stop_when_unstable and self.stopped_because is None:
            self.stopped_because = why
            self.stopped_at = O.time
            O.pause()

    # -- output ---------------------------------------------------------------------------------
    def save(self, prefix):
        """Write the logged history to ``prefix.csv`` and a plot to ``prefix.png``; return both paths.
        Directories are created; nothing already logged is dropped."""
        directory = os.path.dirname(os.path.abspath(prefix))
        os.makedirs(directory, exist_ok=True)
        csv_path, png_path = prefix + '.csv', prefix + '.png'
        write_history_csv(plot.data, csv_path)
        plot_history(plot.data, png_path, title=self.describe(), stopped_at=self.stopped_at)
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


def log_limits(series, decades=7):
    """y limits of a log plot showing the positive values of `series` (lists): from the smallest
    positive value, or `decades` below the largest if that is lower, to a little above the largest."""
    values = [v for s in series for v in s if v > 0 and math.isfinite(v)]
    if not values:
        return None
    top = max(values)
    return max(min(values), top * 10.0 ** -decades) / 2, top * 2


def plot_history(data, path, title='', stopped_at=None):
    """Kinetic and released potential energy (log scale) and the time step against time."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    t = list(data.get('t', []))
    fig, (ax, ax_dt) = plt.subplots(2, 1, figsize=(7, 5.6), sharex=True, gridspec_kw=dict(height_ratios=(2, 1)))
    series = []
    for key, label in (('Ek', 'kinetic energy'), ('Ereleased', 'released potential energy')):
        ys = list(data.get(key, []))
        # log scale: non-positive values (the start, before anything moved) are left out, not clamped
        pts = [(x, y) for x, y in zip(t, ys) if y > 0 and math.isfinite(y)]
        if pts:
            ax.semilogy(*zip(*pts), label=label)
            series.append([y for _, y in pts])
    limits = log_limits(series)
    if limits:
        ax.set_ylim(*limits)
    if stopped_at is not None:
        for a in (ax, ax_dt):
            a.axvline(stopped_at, color='tab:red', linestyle=':', linewidth=1.2)
        ax.annotate('stopped: unstable', (stopped_at, 1), xycoords=('data', 'axes fraction'), xytext=(-4, -12),
                    textcoords='offset points', ha='right', color='tab:red', fontsize=8)
    ax.set_ylabel('energy [J]')
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8, loc='lower right')
    ax.grid(True, which='both', alpha=0.3)
    dts = [(x, y) for x, y in zip(t, data.get('dt', [])) if y > 0]
    if dts:
        ax_dt.semilogy(*zip(*dts), color='tab:gray', label='time step')
    ax_dt.set_ylabel('Δt [s]')
    ax_dt.set_xlabel('time [s]')
    ax_dt.grid(True, which='both', alpha=0.3)
    if 'bridges' in data:
        from matplotlib.ticker import MaxNLocator
        ax_b = ax_dt.twinx()
        ax_b.plot(t, data['bridges'], color='tab:green', linewidth=1)
        ax_b.set_ylabel('bridges', color='tab:green')
        ax_b.yaxis.set_major_locator(MaxNLocator(integer=True))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _floor_of_spheres(width, radius, material):
    """A square lattice of fixed spheres at z = 0 covering a periodic cell of side `width`: a floor a
    periodic cell allows (YADE's collider cannot take an infinite wall inside a periodic cell).
    Spacing 2r with r ≤ `radius`, so the lattice tiles the cell exactly and its holes (0.41 r) let
    no particle of radius ≥ `radius` through.  Returns (ids, radius used)."""
    k = max(2, int(math.ceil(width / (2 * radius))))
    r = width / (2 * k)
    ids = []
    for i in range(k):
        for j in range(k):
            ids.append(O.bodies.append(utils.sphere(((i + 0.5) * 2 * r, (j + 0.5) * 2 * r, 0), r, fixed=True, material=material)))
    return ids, r


def _check_settling_args(n, radius, sizeRatio, density, young, poisson, friction, dt, safety, seed, width, height,
                         periodic, gravity, initialSpeed, integration, trackEnergy, guard):
    f = 'settling'
    _checks.integer(f, 'n', n, minimum=1)
    _checks.integer(f, 'seed', seed)
    for name, value, unit in (('radius', radius, ' [m]'), ('density', density, ' [kg/m³]'), ('young', young, ' [Pa]'),
                              ('gravity', gravity, ' [m/s²]')):
        _checks.positive(f, name, value, unit)
    _checks.in_range(f, 'sizeRatio', sizeRatio, 1, 5)
    _checks.in_range(f, 'poisson', poisson, -1, 0.5, lo_open=True, hi_open=True)
    _checks.non_negative(f, 'friction', friction, ' [rad]')
    _checks.non_negative(f, 'initialSpeed', initialSpeed, ' [m/s]')
    for name, value, unit in (('dt', dt, ' [s]'), ('width', width, ' [m]'), ('height', height, ' [m]')):
        if value is not None:
            _checks.positive(f, name, value, unit + ' or None')
    if safety is not None:
        _checks.in_range(f, 'safety', safety, 0, 1, lo_open=True)
    for name, value in (('periodic', periodic), ('trackEnergy', trackEnergy), ('guard', guard)):
        _checks.boolean(f, name, value)
    _checks.choice(f, 'integration', integration, criteria.INTEGRATIONS)


def settling(n=300, radius=0.5e-3, sizeRatio=1.0, density=2500.0, young=1e7, poisson=0.3, friction=0.5,
             viscosity=1.0, dt=None, safety=None, seed=1, width=None, height=None, periodic=False,
             gravity=9.81, initialSpeed=0.0, integration='explicit', trackEnergy=True, guard=True,
             cloudFraction=0.2, **effects):
    """Build a settling scene in O (which is reset) and return a :class:`Settling` handle.

    n spheres of mean radius `radius` [m] (radii uniform in a range with max/min = sizeRatio, 1–5)
    are placed at random, without contact, in a column of square cross-section `width` (default
    10 mean diameters) and height `height` (default: a loose cloud of solid fraction `cloudFraction`,
    at most 0.27, beyond which random placement fails), above a
    floor.  The sides are walls and the floor a wall; with periodic=True the column is periodic in
    x and y and the floor a layer of fixed spheres (a periodic cell allows no infinite wall).  They
    settle under `gravity` [m/s²] through liquid of `viscosity` [Pa·s]; the other liquid and model
    parameters (sMin/sMinRel, bridgeVolume/bridgeVolumeRel, contactAngle, normalModel,
    tangentialModel, capillaryModel, surfaceTension, formationDistance, en) are those of
    :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys`.

    dt: a fixed time step [s], or None for ViscBridgeTimeStepper with `safety` (None: its default).
    initialSpeed: random initial velocities of this magnitude [m/s] (to start with motion).
    seed: random seed of the positions (and velocities).
    """
    _check_settling_args(n, radius, sizeRatio, density, young, poisson, friction, dt, safety, seed, width, height,
                         periodic, gravity, initialSpeed, integration, trackEnergy, guard)
    _checks.in_range('settling', 'cloudFraction', cloudFraction, 0, 0.27, lo_open=True)
    n, seed = int(n), int(seed)
    ip2_args, rest = bridge_parameters(viscosity=viscosity, **effects)
    if rest:
        raise ValueError('settling: unknown parameter(s) %s' % ', '.join(sorted(rest)))

    O.reset()
    plot.reset()
    fuzz = (sizeRatio - 1.0) / (sizeRatio + 1.0)
    r_min = radius * (1 - fuzz)
    width = width or 20 * radius
    mean_volume = 4.0 / 3.0 * math.pi * radius ** 3 * (1 + fuzz ** 2)
    height = height or max(n * mean_volume / (cloudFraction * width * width), 8 * radius)
    mat = O.materials.append(yw.FrictMat(young=young, poisson=poisson, density=density, frictionAngle=friction))

    sp = pack.SpherePack()
    if periodic:
        O.periodic = True
        O.cell.setBox(width, width, 4 * height)
        placed = sp.makeCloud((0, 0, 0), (width, width, height), rMean=radius, rRelFuzz=fuzz, num=n, periodic=True, seed=seed)
    else:
        placed = sp.makeCloud((0, 0, 0), (width, width, height), rMean=radius, rRelFuzz=fuzz, num=n, seed=seed)
    if placed < n:
        raise ValueError('settling: only %d of n=%d spheres fit in width=%g m × height=%g m; allowed: a larger '
                         'width or height' % (placed, n, width, height))
    if periodic:
        walls, floor_r = _floor_of_spheres(width, r_min, mat)
        lift = floor_r + 1.01 * radius * (1 + fuzz)  # the periodic cloud's own z range starts at 0
    else:
        walls = [O.bodies.append(utils.wall(0, axis=2, sense=1, material=mat))]
        walls += [O.bodies.append(utils.wall(p, axis=a, material=mat)) for a in (0, 1) for p in (0, width)]
        lift = 0.01 * radius
    ids = sp.toSimulation(material=mat)
    if periodic:  # toSimulation() made the cell the cloud's own periodic box: give it its full height back
        O.cell.setBox(width, width, 4 * height)
    for i in ids:
        O.bodies[i].state.pos += (0, 0, lift)

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
                  cloudFraction=cloudFraction, sMin=0.0, sMinRel=1e-3)
    params.update(ip2_args)
    return Settling(params, walls, {i: O.bodies[i].state.pos[2] for i in ids})
