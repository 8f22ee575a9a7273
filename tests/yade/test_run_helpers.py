"""The package's own runs (viscbridge._yade_run: a scan's trials, Drum.run, the ringing measure)
raise when an engine stopped them, also when it threw at the very first step, where YADE's
O.run(n, True) returns in some runs without the error (tests/yade/conftest.py, run_error); and
they leave the user's __main__ alone."""
import pytest
from yade import O
import yade.wrapper as yw

from viscbridge._yade_run import run_steps, run_until


def scene_failing_at(step):
    O.engines = [yw.ForceResetter(), yw.NewtonIntegrator(),
                 yw.PyRunner(iterPeriod=1, initRun=True, command='if O.iter >= %d: raise ValueError("planted")' % step)]
    O.dt = 1e-3


@pytest.mark.parametrize('run', [lambda: run_steps(5), lambda: run_until(O.time + 5e-3)], ids=['steps', 'until'])
def test_an_error_at_the_first_step_is_raised_every_time(run):
    for _ in range(30):
        O.reset()
        scene_failing_at(0)
        with pytest.raises(RuntimeError, match='planted|stopped at step 0'):
            run()
        assert O.iter == 0


def test_an_error_later_in_the_run_is_raised():
    scene_failing_at(3)
    with pytest.raises(RuntimeError, match='planted|stopped at step 3'):
        run_steps(10)
    assert O.iter == 3


def test_a_run_without_error_goes_exactly_as_far_as_asked():
    scene_failing_at(10 ** 9)
    run_steps(1)
    run_steps(7)
    assert O.iter == 8
    run_until(O.time + 0.0105)
    assert O.iter == 19 and O.time == pytest.approx(0.019) and not O.running


def test_a_run_leaves_the_users_names_in_main_alone():
    """YADE's PyRunner copies the locals of the Python frame that took the step into __main__ (when
    the step runs in the caller's thread, as O.step() does): a user's `time` module once became the
    helper's float argument."""
    import __main__
    import time
    scene_failing_at(10 ** 9)
    __main__.time, __main__.steps = time, 'mine'
    try:
        run_steps(3)
        run_until(O.time + 0.0025)
        assert __main__.time is time and __main__.steps == 'mine'
    finally:
        del __main__.time, __main__.steps
