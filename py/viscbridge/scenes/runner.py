"""The handle of a settling scene living in O (:class:`Settling`): its measures, runs that log the
history and stop when the run turns unstable or ViscBridgeGuard stops it, settling until rest, and
saving the history.  The runs log through a PyRunner whose command calls ``_log``.
"""
import os

from yade import O, plot
import yade.wrapper as yw

from .. import _checks, liquid, measures
from ..measures import capillary_input, instability
from .history import plot_history, write_history_csv

__all__ = ['Settling']


class Settling:
    """A settling scene living in O; see :func:`settling`."""

    def __init__(self, params, walls, heights):
        self.params = params
        self.walls = walls
        self._z0 = heights              # initial height of every dynamic body
        self.initial_kinetic = measures.kinetic_energy()
        self._capillary0 = capillary_input()
        self.stopped_because = None
        self.stopped_at = None          # simulated time of the stop, if the run was stopped

    # -- measures -------------------------------------------------------------------------------
    def released_energy(self):
        """Potential energy released since the start: Σ m g (z₀ − z) [J]."""
        return measures.released_energy(self._z0, self.params['gravity'])

    def kinetic_energy(self):
        """Translational + rotational kinetic energy of all bodies [J]."""
        return measures.kinetic_energy()

    def bridges(self):
        """Number of interactions with a liquid bridge."""
        return measures.bridge_count()

    def unstable(self):
        """The instability criterion (:func:`instability`) applied now, the capillary forces' input
        counted with the released potential energy; None while stable."""
        released = measures.energy_released(self._z0, self.params['gravity'], self._capillary0)
        return instability(self.kinetic_energy(), released, self.initial_kinetic)

    def guard(self):
        """The scene's ViscBridgeGuard, or None."""
        return next((e for e in O.engines if isinstance(e, yw.ViscBridgeGuard)), None)

    def time_stepper(self):
        """The scene's ViscBridgeTimeStepper, or None (a fixed time step)."""
        return next((e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper)), None)

    # -- running --------------------------------------------------------------------------------
    def record(self):
        """Append one row to yade.plot.data (called by the scene's PyRunner)."""
        row = dict(t=O.time, iter=O.iter, dt=O.dt, Ek=self.kinetic_energy(), Ereleased=self.released_energy(),
                   bridges=self.bridges())
        stepper = self.time_stepper()
        if stepper is not None:  # how accurate the run was, and which scheme ran (physics.md A2, A5)
            row.update(errorEstimate=stepper.errorEstimate, implicit=int(stepper.scheme == 'implicit'))
        if O.trackEnergy:
            row.update(('E_' + k, v) for k, v in O.energy.items())
            row['Etotal'] = O.energy.total()
        if self.params.get('liquidModel') == 'film':
            spread = liquid.distribution()
            row.update(liquidFilms=liquid.in_films(), liquidBridges=liquid.in_bridges(), liquidCoV=spread.cov)
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
            with _quiet_expected_stops(guard is not None):
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


class _quiet_expected_stops:
    """While a run with a guard goes on: a guard stop is a result that run() returns (its diagnosis
    in our words), not the "FATAL ERROR ... Exception occured" YADE's ThreadRunner logs for any
    exception in an engine, nor the "ERROR ... Simulation error encountered" of O.wait().  Any
    other error still reaches the caller as RuntimeError."""

    LOGGERS = ('ThreadRunner', 'yadeWrapper.cpp')

    def __init__(self, active):
        self.active = active

    def __enter__(self):
        if self.active:
            from yade import log
            for name in self.LOGGERS:
                log.setLevel(name, 0)  # below FATAL: nothing

    def __exit__(self, *exc):
        if self.active:
            from yade import log
            for name in self.LOGGERS:
                log.unsetLevel(name)
        return False


_ACTIVE = [None]
_LOG_COMMAND = 'import viscbridge.scenes; viscbridge.scenes._log()'


def _log():
    """PyRunner hook of :meth:`Settling.run`."""
    if _ACTIVE[0] is not None:
        _ACTIVE[0]._log()

