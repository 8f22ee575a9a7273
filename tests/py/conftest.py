"""pytest set-up shared by every YADE test: YADE runs in-process, one fresh scene per test."""
import pytest

import yade  # noqa: F401  (boots YADE with the plugin overlay on YADE_PREFIX)
from yade import O


@pytest.fixture(autouse=True)
def fresh_scene():
    """Every test starts from an empty scene and leaves none behind."""
    O.reset()
    yield O
    O.pause()
    O.wait()
    O.reset()
