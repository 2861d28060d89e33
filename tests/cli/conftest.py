"""CLI tests run with MTCAL_DEBUG=1: an unexpected exception (a bug) fails the test with its traceback."""

import pytest


@pytest.fixture(autouse=True)
def _debug(monkeypatch):
    monkeypatch.setenv("MTCAL_DEBUG", "1")
