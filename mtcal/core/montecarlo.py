"""Streaming Monte Carlo: simulate → filter → metrics in time chunks, in bounded memory.

A 1000-trial × 60 s × 1 kHz run holds 1.4 GB per (trials, samples, 3) array;
when only metrics are needed, nothing of that size is ever materialised:
:class:`~mtcal.core.simulate.ImuStream` produces chunks, each *consumer* updates
its filter state and folds the chunk's errors into running per-trial
statistics (:class:`ErrorAccumulator`), and the chunk is dropped. Because the
stream's random draws do not depend on the chunk size, the numbers do not
either (tested).

A progress bar (tqdm) is shown when run interactively (a terminal or a
Jupyter kernel) and never when ``MTCAL_PROGRESS=0`` (set by the Makefile, so
nbval/CI outputs stay clean) or when stderr is not interactive.
"""

from __future__ import annotations

import os
import sys
from typing import Iterable, Protocol

import numpy as np

from mtcal.core.validate import as_float_array, positive_int
from mtcal.core.simulate import ImuRecord, ImuStream

__all__ = ["ChunkConsumer", "ErrorAccumulator", "run_streaming", "progress_enabled"]


class ChunkConsumer(Protocol):
    """Anything with ``update(chunk: ImuRecord) -> None``."""

    def update(self, chunk: ImuRecord) -> None: ...


class ErrorAccumulator:
    """Running per-trial RMSE, MaxAE and mean of an error signal.

    Parameters
    ----------
    shape : tuple of int
        Shape of the per-sample error without the sample axis, e.g.
        ``(trials, 3)`` for three angles or ``(trials,)`` for one; errors are
        added as ``(trials, n, …)`` with samples on axis 1 (axis 0 for ``()``).
    """

    def __init__(self, shape: tuple[int, ...]):
        self.shape = tuple(int(s) for s in shape)
        self._sum = np.zeros(self.shape)
        self._sumsq = np.zeros(self.shape)
        self._max = np.zeros(self.shape)
        self._count = np.zeros(self.shape)

    def add(self, error, mask=None) -> None:
        """Fold errors of one chunk in; ``mask`` (n,) selects samples to count."""
        err = as_float_array(error, "error", allow_empty=True)
        axis = min(1, len(self.shape))  # samples follow the trial axis
        expected = self.shape[:axis] + (err.shape[axis],) + self.shape[axis:]
        if err.shape != expected:
            raise ValueError(f"error must have shape {expected} (samples on axis {axis}), got {err.shape}")
        if mask is not None:
            m = np.asarray(mask)
            if m.dtype != bool or m.shape != (err.shape[axis],):
                raise ValueError(f"mask must be a boolean array of shape ({err.shape[axis]},)")
            err = np.compress(m, err, axis=axis)
        self._sum += err.sum(axis=axis)
        self._sumsq += np.einsum("...,...->...", err, err).sum(axis=axis)
        if err.shape[axis]:
            np.maximum(self._max, np.abs(err).max(axis=axis), out=self._max)
        self._count += err.shape[axis]

    def _checked_count(self) -> np.ndarray:
        if np.any(self._count == 0):
            raise ValueError("no samples were accumulated")
        return self._count

    def rmse(self) -> np.ndarray:
        """Root-mean-square error per trial/channel."""
        return np.sqrt(self._sumsq / self._checked_count())

    def mean(self) -> np.ndarray:
        """Mean error per trial/channel."""
        return self._sum / self._checked_count()

    def max_abs(self) -> np.ndarray:
        """Maximum absolute error per trial/channel."""
        self._checked_count()
        return self._max.copy()


def progress_enabled() -> bool:
    """Whether to show a progress bar: never if ``MTCAL_PROGRESS=0``, else when interactive."""
    env = os.environ.get("MTCAL_PROGRESS")
    if env is not None:
        return env not in ("0", "false", "no", "")
    if os.environ.get("CI"):
        return False
    return bool(getattr(sys.stderr, "isatty", lambda: False)()) or "ipykernel" in sys.modules


def run_streaming(stream: ImuStream, consumers: Iterable[ChunkConsumer], chunk_samples: int = 1000,
                  *, progress: bool | None = None) -> None:
    """Feed every chunk of ``stream`` to each consumer in turn.

    Parameters
    ----------
    stream : ImuStream
        Simulated IMU output (trials on a leading axis).
    consumers : iterable of ChunkConsumer
        Objects whose ``update(chunk)`` advances a filter and accumulates metrics.
    chunk_samples : int
        Samples per chunk; memory is O(trials × chunk_samples).
    progress : bool, optional
        Force the progress bar on/off (default: :func:`progress_enabled`).
    """
    if not isinstance(stream, ImuStream):
        raise TypeError(f"stream must be an ImuStream, got {type(stream).__name__}")
    consumers = list(consumers)
    if not consumers or not all(callable(getattr(c, "update", None)) for c in consumers):
        raise TypeError("consumers must be a non-empty list of objects with an update(chunk) method")
    size = positive_int(chunk_samples, "chunk_samples")
    n_chunks = -(-len(stream.trajectory) // size)
    chunks = stream.chunks(size)
    if progress_enabled() if progress is None else progress:
        from tqdm.auto import tqdm

        chunks = tqdm(chunks, total=n_chunks, desc="Monte Carlo", unit="chunk", leave=False)
    for chunk in chunks:
        for consumer in consumers:
            consumer.update(chunk)
