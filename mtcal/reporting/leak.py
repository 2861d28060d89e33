"""Leak test harness: the fit and its predictions must not read a held-out paper number.

Each study registers one function ``fit_and_predict(size="ci", seed=0) -> dict[str, ndarray]``
(:func:`register`) returning its fitted parameters and predictive bands. :func:`check_no_leak`
copies ``paper_data`` to a temporary folder, replaces every ``heldout`` and ``tuned`` value of the
split (:func:`mtcal.reporting.paper_numbers.split`; :data:`PERTURBED_ROLES`: a ``tuned`` number is one no fit
reads, so perturbing it must change nothing either) by garbage (:data:`PERTURBATIONS`:
×1000, shifted, NaN, negated), points ``MTCAL_PAPER_DIR`` at the copy, re-runs the
function and asserts bit-identical outputs. A registered function must compute
from scratch on every call (no cache keyed on anything but its arguments).

References
----------
Issue #21 item 2 (a leak test in ``make test``).

Examples
--------
>>> perturb_text("0.5", "scale"), perturb_text("0.0827", "nan"), perturb_text("±5", "shift")
('500.0', 'nan', 'nan')
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from . import paper_numbers

__all__ = ["PERTURBATIONS", "PERTURBED_ROLES", "register", "registered", "perturb_text", "perturbed_copy", "paper_dir_override",
           "differences", "check_no_leak"]

#: Garbage written over every held-out value: scaled ×1000, shifted by +123.456, NaN, negated.
PERTURBATIONS = ("scale", "shift", "nan", "negate")
#: Split roles whose values the fits must not read (perturbed together).
PERTURBED_ROLES = ("heldout", "tuned")
_REGISTRY: dict[str, Callable] = {}


def register(key: str):
    """Decorator: register ``fn(size="ci", seed=0) -> dict[str, ndarray]`` as paper ``key``'s fit + predictions.

    >>> saved = registered().get("tan2022")
    >>> @register("tan2022")
    ... def fake(size="ci", seed=0):
    ...     return {"x": np.zeros(1)}
    >>> registered()["tan2022"] is fake
    True
    >>> _ = register("tan2022")(saved) if saved else _REGISTRY.pop("tan2022")
    """
    if key not in paper_numbers.KEYS:
        raise ValueError(f"key must be one of {paper_numbers.KEYS}, got {key!r}")

    def deco(fn):
        if not callable(fn):
            raise TypeError(f"fit_and_predict must be callable, got {type(fn).__name__}")
        _REGISTRY[key] = fn
        return fn
    return deco


def registered() -> dict[str, Callable]:
    """The registered ``fit_and_predict`` functions by paper key (import the studies first)."""
    return dict(_REGISTRY)


def perturb_text(text: str, mode: str) -> str:
    """Garbage for one printed number (``mode`` in :data:`PERTURBATIONS`); non-plain numbers become ``nan``."""
    if mode not in PERTURBATIONS:
        raise ValueError(f"mode must be one of {PERTURBATIONS}, got {mode!r}")
    try:
        v = float(text)
    except (TypeError, ValueError):
        return "nan"
    if mode == "nan" or not np.isfinite(v):
        return "nan"
    out = {"scale": v * 1000.0, "shift": v + 123.456, "negate": -v - 1.0}[mode]
    return repr(float(out))


def perturbed_copy(dst: str | Path, mode: str, keys=paper_numbers.KEYS) -> Path:
    """Copy the current paper folder to ``dst`` with every held-out and tuned value of ``keys`` perturbed; return ``dst``."""
    src, dst = paper_numbers.paper_dir(), Path(dst)
    if dst.exists() and any(dst.iterdir()):
        raise ValueError(f"dst must be empty or absent, got {dst}")
    shutil.copytree(src, dst, dirs_exist_ok=True)
    for key in keys:
        sp = paper_numbers.split(key)
        held = sp[sp["role"].isin(PERTURBED_ROLES)]
        for name, part in held.groupby("file", sort=True):
            path = dst / f"{name}.csv"
            df = pd.read_csv(path, dtype=str, keep_default_na=False)
            for r in part.itertuples():
                df.at[r.row - 1, r.column] = perturb_text(r.text, mode)
            df.to_csv(path, index=False, lineterminator="\n")
    return dst


@contextlib.contextmanager
def paper_dir_override(path: str | Path):
    """Context manager: ``MTCAL_PAPER_DIR=path`` inside, the previous value restored after."""
    old = os.environ.get("MTCAL_PAPER_DIR")
    os.environ["MTCAL_PAPER_DIR"] = str(path)
    try:
        yield Path(path)
    finally:
        if old is None:
            os.environ.pop("MTCAL_PAPER_DIR", None)
        else:
            os.environ["MTCAL_PAPER_DIR"] = old


def differences(a: dict, b: dict) -> list[str]:
    """Names of the outputs that are not bit-identical (missing keys, dtype, shape or bytes differ).

    >>> differences({"p": np.array([1.0, np.nan])}, {"p": np.array([1.0, np.nan])})
    []
    >>> differences({"p": np.array([1.0])}, {"p": np.array([1.0 + 1e-16 * 3])})
    ['p']
    """
    out = []
    for k in sorted(set(a) | set(b)):
        if k not in a or k not in b:
            out.append(k)
            continue
        x, y = np.asarray(a[k]), np.asarray(b[k])
        if x.dtype != y.dtype or x.shape != y.shape or x.tobytes() != y.tobytes():
            out.append(k)
    return out


def check_no_leak(key: str, fn: Callable | None = None, *, size: str = "ci", seed: int = 0,
                  perturbations=PERTURBATIONS) -> dict:
    """Run paper ``key``'s fit + predictions on the real and on perturbed paper data; assert bit-identity.

    Parameters
    ----------
    key : str
        Paper key (its split defines the held-out cells).
    fn : callable, optional
        ``fn(size=..., seed=...) -> dict[str, ndarray]``; default the registered one.
    size, seed
        Passed to ``fn``.
    perturbations : sequence of str
        Modes of :func:`perturb_text`.

    Returns
    -------
    dict
        The reference outputs (unperturbed data).

    Raises
    ------
    AssertionError
        Naming the perturbation and the outputs that changed: a leak.
    """
    if fn is None:
        if key not in _REGISTRY:
            raise ValueError(f"no fit_and_predict registered for {key!r}; registered: {sorted(_REGISTRY)}")
        fn = _REGISTRY[key]
    if not perturbations:
        raise ValueError("perturbations must not be empty")
    ref = fn(size=size, seed=seed)
    if not isinstance(ref, dict) or not ref:
        raise TypeError(f"fit_and_predict must return a non-empty dict of arrays, got {type(ref).__name__}")
    for mode in perturbations:
        with tempfile.TemporaryDirectory(prefix="mtcal-leak-") as tmp:
            path = perturbed_copy(Path(tmp) / "paper_data", mode, keys=(key,))
            with paper_dir_override(path):
                out = fn(size=size, seed=seed)
        diff = differences(ref, out)
        if diff:
            raise AssertionError(f"leak in {key}: with held-out and tuned values perturbed ({mode!r}) these outputs "
                                 f"changed: {diff}")
    return ref
