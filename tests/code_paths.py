"""Run a check in a fresh process on the other numba/numpy code path (generic <-> native).

``make test`` runs on the pinned generic path (:func:`mtcal.runs.environment.numerics_env`);
``make bench`` and users run natively. A test that claims "bit-identical to numpy on both paths"
runs its check here a second time on the path the suite is not on.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from mtcal.runs.environment import numerics_env

ROOT = Path(__file__).resolve().parents[1]
#: Variables the Makefile's NATIVE_ENV unsets to leave the pinned path.
_PINNED_CODE_PATH = ("NUMBA_CPU_NAME", "NPY_DISABLE_CPU_FEATURES", "GLIBC_TUNABLES")


def run_on_the_other_code_path(code: str) -> subprocess.CompletedProcess:
    """``python -c code`` from the repository root on the other code path; returns the finished process."""
    env = dict(os.environ)
    if env.get("NUMBA_CPU_NAME") == "generic":  # the suite runs generic (make test): check native (make bench)
        for var in _PINNED_CODE_PATH:
            env.pop(var, None)
    else:
        env.update(numerics_env())
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    return subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True, text=True)
