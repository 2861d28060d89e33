"""mtcal.runs.environment: the pinned numerics environment and temporary environment variables."""

import os

import pytest

from mtcal.runs.environment import environment, numerics_env, repo_root


def test_numerics_env_pins_one_thread_one_kernel_set_and_generic_code():
    env = numerics_env()
    assert env["OPENBLAS_NUM_THREADS"] == env["OMP_NUM_THREADS"] == env["MKL_NUM_THREADS"] == "1"
    assert env["OPENBLAS_CORETYPE"] == "Nehalem" and env["NUMBA_CPU_NAME"] == "generic"
    assert "FMA" in env["GLIBC_TUNABLES"] and env["NPY_DISABLE_CPU_FEATURES"].strip()


def test_environment_sets_unsets_and_restores(monkeypatch):
    monkeypatch.setenv("MTCAL_T_KEEP", "old")
    monkeypatch.delenv("MTCAL_T_NEW", raising=False)
    with environment({"MTCAL_T_KEEP": None, "MTCAL_T_NEW": "1"}):
        assert "MTCAL_T_KEEP" not in os.environ and os.environ["MTCAL_T_NEW"] == "1"
    assert os.environ["MTCAL_T_KEEP"] == "old" and "MTCAL_T_NEW" not in os.environ
    with pytest.raises(RuntimeError, match="inside"):
        with environment({"MTCAL_T_NEW": "2"}):
            raise RuntimeError("inside")
    assert "MTCAL_T_NEW" not in os.environ


def test_repo_root_is_this_checkout():
    root = repo_root()
    assert root is not None and (root / "mtcal" / "runs" / "environment.py").is_file()
