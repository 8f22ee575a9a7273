"""pytest set-up of the in-process YADE tier (tests/yade): YADE runs in this process (the plugin
overlay on YADE_PREFIX, as ctest sets it), one fresh scene per test.

A file whose tests need long YADE runs marks itself ``pytestmark = pytest.mark.slow``: ctest then
leaves it out of the fast tier (``./yadew test --fast``; tests/CMakeLists.txt reads that line).
Small scenes for the physics tests: wetpairs.py."""
import re

import pytest

import yade  # noqa: F401  (boots YADE with the plugin overlay on YADE_PREFIX)
from yade import O


def pytest_configure(config):
    config.addinivalue_line('markers', 'slow: a long YADE run; the file is not in the fast tier (./yadew test --fast)')


@pytest.fixture(autouse=True)
def fresh_scene():
    """Every test starts from an empty scene and leaves none behind."""
    O.reset()
    yield O
    O.pause()
    O.wait()
    O.reset()


@pytest.fixture
def run_error(capfd):
    """run_error(n): O.run(n, True) must stop on an exception; returns its message.

    YADE's O.wait() (py/wrapper/yadeWrapper.cpp) returns without re-raising when the worker thread
    has already stopped by the time it first polls, which happens when the very first step fails
    quickly. The exception then only reaches the log ("Exception occured: ..."), so it is read from
    there; either way the run must have stopped on it."""
    def run(steps):
        capfd.readouterr()  # forget what earlier steps printed
        try:
            O.run(steps, True)
        except RuntimeError as error:
            return str(error)
        logged = re.search(r'Exception occured: *\n(.*)', capfd.readouterr().err, re.S)
        assert logged, 'O.run(%d) ended without an error' % steps
        assert not O.running
        return logged.group(1).strip()
    return run
