"""Running YADE steps from the package's own helpers without going on past an engine's error.

YADE's ``O.run(n, True)`` starts the step thread and then polls it; when the thread throws and stops
before the first poll (an error at the very first step of a run: every refusal of a scene does
this), ``O.wait()`` sees a stopped simulation and returns normally, and the error is only printed
("FATAL ERROR ... Exception occured").  On a loaded machine this happens in some runs and not in
others.  The helpers here check that the run went as far as asked and raise otherwise.

(``O.step()`` would raise the engine's own exception, but it runs the step in the caller's thread,
where YADE's PyRunner copies the calling function's local variables into ``__main__`` — a user's
``time`` module became a float — and a ViscBridgeRecorder takes a step outside a run as a run's end.)
"""

__all__ = ['run_steps', 'run_until']


def run_steps(steps):
    """Advance exactly `steps` steps; RuntimeError if an engine stopped the run before."""
    from yade import O
    target, before = O.iter + steps, _guard_errors()
    O.run(steps, True)
    if O.iter < target:
        raise RuntimeError(_stopped_short('step %d' % target, before))


def run_until(time):
    """Advance until the simulation time reaches `time` [s] (YADE's ``O.stopAtTime``); RuntimeError
    if an engine stopped the run before."""
    from yade import O
    before = _guard_errors()
    O.stopAtTime = time
    try:
        O.run(-1, True)
    finally:
        O.stopAtTime = 0
    if O.time < time:
        raise RuntimeError(_stopped_short('t = %g s' % time, before))


def _guard_errors():
    from yade import O
    import yade.wrapper as yw
    return [e.lastError for e in O.engines if isinstance(e, yw.ViscBridgeGuard)]


def _stopped_short(goal, before):
    """The guard's new error, else what YADE printed and did not pass on."""
    from yade import O
    new = [error for error in _guard_errors() if error and error not in before]
    return new[0] if new else ('the run stopped at step %d (t = %g s) before reaching %s: an engine threw the error '
                               'YADE printed above ("Exception occured:") and did not pass on' % (O.iter, O.time, goal))
