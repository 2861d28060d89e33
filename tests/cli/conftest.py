"""CLI tests run with MTCAL_DEBUG=1: an unexpected exception (a bug) fails the test with its traceback."""

import pytest


@pytest.fixture(autouse=True)
def _debug(monkeypatch):
    monkeypatch.setenv("MTCAL_DEBUG", "1")


@pytest.fixture(scope="module")
def heavy(tmp_path_factory):
    """A hinge log whose sensor reads |a| ~ 9.97 m/s^2 (1.7 % scale error): outside the paper's band."""
    from tests.cli import logs

    return logs.hinge_log(g_error=0.017).write(tmp_path_factory.mktemp("heavy") / "hinge.csv")
