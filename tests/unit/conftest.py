"""pytest set-up of the unit tier (tests/unit): pure Python, no YADE.

These tests run in any Python 3 with numpy and scipy and the repository's py/ on PYTHONPATH (ctest
sets it; by hand: ``PYTHONPATH=py python3 -m pytest tests/unit``), without YADE or a built plugin —
except the registry and golden-number checks, which run the built ``viscbridge_registry`` tool
(VISCBRIDGE_REGISTRY_TOOL, else $VISCBRIDGE_BUILD/viscbridge_registry).  A test that imports YADE,
directly or through a module it uses, fails: it belongs to tests/yade.
"""
import sys

import pytest


@pytest.fixture(autouse=True)
def no_yade():
    """Fail a test after which YADE is loaded in this process."""
    yield
    assert 'yade' not in sys.modules, 'this test imported YADE: it belongs to tests/yade, not tests/unit'
