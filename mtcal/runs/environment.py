"""The numerics environment of every notebook run: floating-point results independent of the x86-64 CPU.

Numerics are pinned for every run (:func:`numerics_env`): one BLAS thread,
OpenBLAS's ``Nehalem`` kernels, numpy's baseline (non-dispatched) SIMD loops and
glibc's SSE2 libm variants, so the last bits of a result do not depend on which
x86-64 CPU runs it (AVX-512 SVML loops in numpy and FMA variants of ``exp``/``sin``
in glibc change the last bit; the OpenBLAS kernel type changes ``svd``).
:func:`environment` applies such variables for the duration of a block.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

__all__ = ["numerics_env", "repo_root", "environment"]


def numerics_env() -> dict[str, str]:
    """Environment that makes floating-point results independent of the x86-64 CPU.

    * ``OPENBLAS_NUM_THREADS=1`` (and OMP/MKL): no thread-count-dependent blocking;
    * ``OPENBLAS_CORETYPE=Nehalem``: one BLAS/LAPACK kernel set on every CPU that
      numpy's x86-64-v2 baseline runs on (``svd`` differs between SkylakeX and Haswell);
    * ``NPY_DISABLE_CPU_FEATURES``: numpy's dispatched SIMD targets off (on AVX-512
      CPUs numpy uses SVML for ``exp``, ``log``, ``tan``, ``arctan``, ``power``…,
      whose last bits differ from the scalar loops);
    * ``GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX,-AVX2,-FMA,-FMA4``: glibc's SSE2 libm
      variants (the FMA variants of ``sin``/``cos``/``exp``/``atan2`` round differently);
    * ``NUMBA_CPU_NAME=generic``: the compiled filter kernels target generic x86-64.

    The ``Makefile`` exports the same values (tested).

    >>> env = numerics_env()
    >>> env["OPENBLAS_NUM_THREADS"], env["OPENBLAS_CORETYPE"]
    ('1', 'Nehalem')
    """
    from numpy._core import _multiarray_umath as umath

    return {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
            "OPENBLAS_CORETYPE": "Nehalem",
            "NPY_DISABLE_CPU_FEATURES": " ".join(umath.__cpu_dispatch__),
            "GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX,-AVX2,-FMA,-FMA4",
            "NUMBA_CPU_NAME": "generic"}


def repo_root() -> Path | None:
    """The source checkout mtcal runs from (has ``pyproject.toml`` and ``notebooks/``), else None."""
    root = Path(__file__).resolve().parents[2]
    if (root / "pyproject.toml").is_file() and (root / "notebooks").is_dir():
        return root
    return None


@contextlib.contextmanager
def environment(values: dict[str, str | None]):
    """Set environment variables for the duration of a ``with`` block (a ``None`` value unsets one).

    >>> with environment({"MTCAL_PROBE_VAR": "1"}):
    ...     os.environ["MTCAL_PROBE_VAR"]
    '1'
    >>> "MTCAL_PROBE_VAR" in os.environ
    False
    """
    saved = {k: os.environ.get(k) for k in values}
    try:
        _set_environment(values)
        yield
    finally:
        _set_environment(saved)


def _set_environment(values: dict[str, str | None]) -> None:
    """Set each variable to its value; a ``None`` value unsets it."""
    for k, v in values.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v
