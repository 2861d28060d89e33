"""Streaming Monte Carlo: simulate → filter → metrics in time chunks, in bounded memory.

A 1000-trial × 60 s × 1 kHz run holds 1.4 GB per (trials, samples, 3) array;
when only metrics are needed, nothing of that size is ever materialised:
:class:`~mtcal.core.simulate.ImuStream` produces chunks, each *consumer* updates
its filter state and folds the chunk's errors into running per-trial
statistics (:class:`ErrorAccumulator`), and the chunk is dropped. The
simulator draws its noise inside its compiled kernel (counter-based Philox,
:mod:`mtcal.core.philox`), so no noise array of size trials × samples exists
either. Because the stream's random draws do not depend on the chunk size,
the numbers do not either (tested); because they are addressed by trial id
(``ImuStream(..., trial_ids=...)``), a run split across workers gives each
trial the numbers of the whole run (tested).

A progress bar (tqdm) is shown when run interactively (a terminal or a
Jupyter kernel) and never when ``MTCAL_PROGRESS=0`` (set by the Makefile, so
nbval/CI outputs stay clean) or when stderr is not interactive.
"""

from __future__ import annotations

import os
import sys
from typing import Iterable, Protocol

import math

import numba
import numpy as np
from numba import prange

from mtcal.core import metrics, rotations
from mtcal.core.validate import as_float_array, positive_int
from mtcal.core._rotation_kernels import apply_row
from mtcal.core.compiled import jit
from mtcal.core.simulate import ImuRecord, ImuStream

__all__ = ["progress", "ChunkConsumer", "ErrorAccumulator", "run_streaming", "progress_enabled",
           "channel_errors_before_after"]


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

    def add_euler_zxy_errors(self, q_ws, truth_euler_rad) -> None:
        """Fold in the wrapped Eq 8 (wang2023cja) yaw/pitch/roll errors of attitude estimates.

        The numbers of ``add(metrics.angle_difference(rotations.euler_zxy_from_quat(q_ws),
        truth_euler_rad))`` within :data:`ERROR_BOUND_RAD` per sample (:func:`euler_errors_cs`:
        small errors by an odd series instead of 2 atan2 + 1 asin), in one compiled pass over
        the trials in parallel, without the (T, n, 3) temporaries. Needs ``shape == (T, 3)``.

        Parameters
        ----------
        q_ws : array_like, shape (T, n, 4)
            Unit quaternions (scalar-first), e.g. a filter's output for one chunk.
        truth_euler_rad : array_like, shape (n, 3) or (T, n, 3)
            True yaw ψ, pitch θ, roll γ (rad).
        """
        q = np.ascontiguousarray(as_float_array(q_ws, "q_ws", ndim=3, last_dim=4, copy=False))
        tr = as_float_array(truth_euler_rad, "truth_euler_rad", ndim=(2, 3), last_dim=3, copy=False)
        if len(self.shape) != 2 or self.shape[1] != 3 or q.shape[0] != self.shape[0]:
            raise ValueError(f"q_ws must have shape ({self.shape[0]}, n, 4) for an accumulator of shape "
                             f"(trials, 3), got q_ws {q.shape} and accumulator {self.shape}")
        tr3 = np.ascontiguousarray(tr if tr.ndim == 3 else tr[None])
        if tr3.shape[1] != q.shape[1] or tr3.shape[0] not in (1, q.shape[0]):
            raise ValueError(f"truth_euler_rad of shape {tr.shape} does not match q_ws {q.shape}")
        _euler_error_stats(q, tr3, self._sum, self._sumsq, self._max)
        self._count += q.shape[1]

    def _stats_block(self) -> np.ndarray:
        """(T, 9) block [sum ×3, sum of squares ×3, max ×3] for compiled kernels to add into."""
        if len(self.shape) != 2 or self.shape[1] != 3:
            raise ValueError(f"compiled error statistics need an accumulator of shape (trials, 3), got {self.shape}")
        block = np.zeros((self.shape[0], 9))
        block[:, 6:] = self._max
        return block

    def _stats_block_done(self, block: np.ndarray, samples: int) -> None:
        """Fold a block filled by a compiled kernel over ``samples`` samples in."""
        self._sum += block[:, 0:3]
        self._sumsq += block[:, 3:6]
        self._max[:] = block[:, 6:]
        self._count += samples

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


@jit
def _wrap(d):
    """``(d + π) % 2π − π`` of :func:`mtcal.core.metrics.angle_difference`, bit for bit: the remainder
    (Python/numpy semantics) is skipped when ``d + π`` already lies in [0, 2π), where it is the identity."""
    x = d + np.pi
    if 0.0 <= x < 2 * np.pi:
        return x - np.pi
    return x % (2 * np.pi) - np.pi


@numba.njit(inline="always")
def euler_errors(q0, q1, q2, q3, t0, t1, t2):
    """Wrapped Eq 8 errors of one quaternion against truth (ψ, θ, γ), the reference arithmetic of
    ``rotations.euler_zxy_unchecked`` and ``metrics.angle_difference`` (2 atan2 + 1 asin per sample);
    the fast statistics use :func:`euler_errors_cs`, which falls back to this."""
    s00, s11, s22, s33 = q0 * q0, q1 * q1, q2 * q2, q3 * q3
    yaw = math.atan2(-2.0 * (q1 * q2 - q0 * q3), ((s00 - s11) + s22) - s33)
    pitch = math.asin(min(max(2.0 * (q2 * q3 + q0 * q1), -1.0), 1.0))
    roll = math.atan2(-2.0 * (q1 * q3 - q0 * q2), ((s00 - s11) - s22) + s33)
    return _wrap(yaw - t0), _wrap(pitch - t1), _wrap(roll - t2)


#: Bound of the series paths of :func:`euler_errors_cs`: |tan e| < 1/64 (yaw, roll), |sin e| < 1/64 (pitch).
SERIES_MAX = 1.0 / 64.0
#: Stated bound (rad) of |euler_errors_cs − reference| per angle: ``ERROR_BOUND_RAD + ERROR_BOUND_LOCK_RAD / cos θ``
#: (reference: ``metrics.angle_difference(rotations.euler_zxy_from_quat(q), truth)``, numpy's arctan2/arcsin,
#: compared modulo 2π). Measured on 10⁶ random and near-lock quaternions: ≤ 8.9e-16 on the series path,
#: ≤ 1.8e-15 on the fallback (libm vs numpy and the reference's wrap rounding, as before), and ≤ 1.2e-15 / cos θ
#: within cos θ < 1e-3 of gimbal lock, where the reference switches to its half-angle form while both kernels
#: evaluate the ill-conditioned Eq 8 from the same rounded quaternion products. Against long-double arithmetic
#: on the same products the series path errs ≤ 1.9e-16, the reference ≤ 5.2e-16 (the wrap's rounding at ±π).
ERROR_BOUND_RAD = 4e-15
ERROR_BOUND_LOCK_RAD = 2e-15
#: Odd-series coefficients of atan and asin (degree 9) of the series paths.
ATAN_C3, ATAN_C5, ATAN_C7, ATAN_C9 = -1.0 / 3.0, 1.0 / 5.0, -1.0 / 7.0, 1.0 / 9.0
ASIN_C3, ASIN_C5, ASIN_C7, ASIN_C9 = 1.0 / 6.0, 3.0 / 40.0, 5.0 / 112.0, 35.0 / 1152.0


@numba.njit(inline="always")
def atan_small(r):
    """atan(r) for |r| < 1/64: r + r·u·(−1/3 + u(1/5 + u(−1/7 + u/9))), u = r² (truncation < 1e-19 relative)."""
    u = r * r
    return r + r * (u * (ATAN_C3 + u * (ATAN_C5 + u * (ATAN_C7 + u * ATAN_C9))))


@numba.njit(inline="always")
def asin_small(y):
    """asin(y) for |y| < 1/64: y + y·u·(1/6 + u(3/40 + u(5/112 + u·35/1152))), u = y² (truncation < 1e-19)."""
    u = y * y
    return y + y * (u * (ASIN_C3 + u * (ASIN_C5 + u * (ASIN_C7 + u * ASIN_C9))))


@numba.njit(inline="always")
def euler_errors_cs(q0, q1, q2, q3, t0, t1, t2, c0, s0, c1, s1, c2, s2):
    """Wrapped Eq 8 errors of one quaternion against truth angles ``t`` with ``(c, s) = (cos t, sin t)``.

    Each error is the angle of the estimate's Eq 8 vector rotated back by the truth angle:
    yaw/roll ``e = atan2(y c − x s, x c + y s)`` of Eq 8's atan2 pair (x, y), pitch the same with
    ``(x, y) = (cos θ̂, sin θ̂) = (√((1 − a)(1 + a)), a)``, ``a = 2(q2q3 + q0q1)`` — no wrap needed.
    When the rotated vector is within ``SERIES_MAX`` of the +x axis (every sample of a converged
    filter), ``atan(Y/X)`` / ``asin(Y)`` is a degree-9 odd series (division, sqrt, multiply-adds only,
    vectorisable); otherwise the reference :func:`euler_errors`. Agrees with
    ``metrics.angle_difference(rotations.euler_zxy_from_quat(q), t)`` within
    ``ERROR_BOUND_RAD + ERROR_BOUND_LOCK_RAD / cos θ`` (±π wraps compared modulo 2π; tested).
    """
    s00, s11, s22, s33 = q0 * q0, q1 * q1, q2 * q2, q3 * q3
    yx = ((s00 - s11) + s22) - s33
    yy = -2.0 * (q1 * q2 - q0 * q3)
    a = min(max(2.0 * (q2 * q3 + q0 * q1), -1.0), 1.0)
    rx = ((s00 - s11) - s22) + s33
    ry = -2.0 * (q1 * q3 - q0 * q2)
    xa = yx * c0 + yy * s0
    ya = yy * c0 - yx * s0
    ce = math.sqrt((1.0 - a) * (1.0 + a))
    xb = ce * c1 + a * s1
    yb = a * c1 - ce * s1
    xc = rx * c2 + ry * s2
    yc = ry * c2 - rx * s2
    if abs(ya) < SERIES_MAX * xa and abs(yb) < SERIES_MAX and xb > 0.0 and abs(yc) < SERIES_MAX * xc:
        return atan_small(ya / xa), asin_small(yb), atan_small(yc / xc)
    return euler_errors(q0, q1, q2, q3, t0, t1, t2)


@jit
def _truth_table(truth, out):
    """out[..., :] = [ψ, θ, γ, cos ψ, sin ψ, cos θ, sin θ, cos γ, sin γ] of truth (…, 3), with libm."""
    flat = truth.reshape(-1, 3)
    dst = out.reshape(-1, 9)
    for i in range(flat.shape[0]):
        for j in range(3):
            t = flat[i, j]
            dst[i, j] = t
            dst[i, 3 + 2 * j] = math.cos(t)
            dst[i, 4 + 2 * j] = math.sin(t)


def truth_table(truth_euler_rad: np.ndarray) -> np.ndarray:
    """(Tt, n, 9) table of truth angles with their cosines and sines for the compiled error statistics.

    Parameters
    ----------
    truth_euler_rad : ndarray, shape (Tt, n, 3)
        Validated, C-contiguous true yaw, pitch, roll (rad).

    Returns
    -------
    ndarray, shape (Tt, n, 9)
        ``[ψ, θ, γ, cos ψ, sin ψ, cos θ, sin θ, cos γ, sin γ]`` per sample.
    """
    out = np.empty(truth_euler_rad.shape[:-1] + (9,))
    _truth_table(np.ascontiguousarray(truth_euler_rad), out)
    return out


@numba.njit(inline="always")
def table_errors(q0, q1, q2, q3, r):
    """:func:`euler_errors_cs` with the truth row ``r`` of :func:`truth_table`."""
    return euler_errors_cs(q0, q1, q2, q3, r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8])


@jit
def channel_errors_cs(q, q_mat, table, lock_sin, chan, before, after, err_before, err_after):  # pragma: no cover
    """Eq 8 errors of ``q`` (T, N, 4) before and after Eq 10 with ``q_mat`` (T, 4, 4) against one truth
    table (N, 9) (:func:`truth_table`) by :func:`euler_errors_cs`, into ``err_before``/``err_after``
    (T, N, 3), and angle ``chan`` before/after into ``before``/``after`` (T, N) as truth + error.

    Eq 10 is :func:`mtcal.core.rotations.apply_quat_matrix_trusted`'s arithmetic (sign alignment,
    ``q @ q_matᵀ`` summed in index order, the norm, each component divided by it). Each error is within
    ``ERROR_BOUND_RAD`` of the libm reference ``angle_difference(euler_zxy(q), truth)``; each angle within
    that plus one rounding of the reference's, modulo 2π (it is not re-wrapped: a channel whose truth sits
    at ±π may leave (−π, π]). Returns the number of rows left unset — |sin pitch| above ``lock_sin``
    (before or after) or a norm below 1e-12 — which the caller then computes by the reference expressions
    (all rows, when any).
    """
    bad = 0
    for t in range(q.shape[0]):
        m = q_mat[t]
        for i in range(q.shape[1]):
            q0, q1, q2, q3 = q[t, i, 0], q[t, i, 1], q[t, i, 2], q[t, i, 3]
            r = table[i]
            if abs(min(max(2.0 * (q2 * q3 + q0 * q1), -1.0), 1.0)) > lock_sin:
                bad += 1
                continue
            b0, b1, b2, b3, n = apply_row(q0, q1, q2, q3, m)      # Eq 10
            if n < 1e-12:
                bad += 1
                continue
            b0, b1, b2, b3 = b0 / n, b1 / n, b2 / n, b3 / n
            if abs(min(max(2.0 * (b2 * b3 + b0 * b1), -1.0), 1.0)) > lock_sin:
                bad += 1
                continue
            e0, e1, e2 = table_errors(q0, q1, q2, q3, r)
            a0, a1, a2 = table_errors(b0, b1, b2, b3, r)
            err_before[t, i, 0], err_before[t, i, 1], err_before[t, i, 2] = e0, e1, e2
            err_after[t, i, 0], err_after[t, i, 1], err_after[t, i, 2] = a0, a1, a2
            before[t, i] = r[chan] + (e0 if chan == 0 else (e1 if chan == 1 else e2))
            after[t, i] = r[chan] + (a0 if chan == 0 else (a1 if chan == 1 else a2))
    return bad


def channel_errors_before_after(q_s: np.ndarray, q_matrix, reference_rad, chan: int,
                                table: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, dict]:
    """Eq 8 angle ``chan`` of attitudes before and after Eq 10, and the wrapped errors of all three angles.

    The scoring of a calibrated attitude against its reference: ``euler(q_s)[..., chan]``,
    ``euler(apply_quat_matrix_trusted(q_matrix, q_s))[..., chan]`` and
    ``metrics.angle_difference`` of the full angles from ``reference_rad`` (Eq 8 angles: the
    ZXY convention of :func:`mtcal.core.rotations.euler_zxy_unchecked`). A large float64 input with
    finite matrices takes one compiled pass (:func:`channel_errors_cs`): each error the angle of the
    estimate's Eq 8 vector rotated back by the reference — for a converged filter a degree-9 series,
    no atan2/asin — and each angle reference + error, within :data:`ERROR_BOUND_RAD` of the expressions
    (tested). Near gimbal lock, with a non-finite matrix or a small input, the expressions themselves.

    Parameters
    ----------
    q_s : ndarray, shape (T, N, 4)
        Unit attitude quaternions (trusted: a filter's output, float64).
    q_matrix : array_like, shape (T, 4, 4)
        Each trial's calibration matrix (Eq 10).
    reference_rad : array_like, shape (N, 3)
        Reference Eq 8 angles ψ, θ, γ (rad) at each sample, shared by the trials.
    chan : {0, 1, 2}
        The angle returned before and after.
    table : ndarray, shape (N, 9), optional
        ``truth_table(reference_rad[None])[0]`` when the caller keeps it (one per reference).

    Returns
    -------
    before, after : ndarray, shape (T, N)
        Angle ``chan`` (rad) before and after Eq 10.
    errors : dict
        ``"before"``, ``"after"``: wrapped errors (T, N, 3) (rad) of the three angles.

    Raises
    ------
    FloatingPointError
        If an angle is not finite (a NaN calibration matrix or attitude).

    Examples
    --------
    >>> q = rotations.quat_from_euler_zxy(np.zeros(3), np.radians([1.0, 2.0, 3.0]), np.zeros(3))[None]
    >>> m = rotations.left_matrix(rotations.quat_from_euler_zxy(0.0, np.radians(-1.0), 0.0))[None]
    >>> before, after, errs = channel_errors_before_after(q, m, np.radians([[0, 1, 0], [0, 1, 0], [0, 2, 0]]), 1)
    >>> np.degrees(after).round(9).tolist(), np.degrees(errs["before"][..., 1]).round(9).tolist()
    ([[0.0, 1.0, 2.0]], [[0.0, 1.0, 1.0]])
    """
    q_matrix = np.asarray(q_matrix, float)
    if (q_s.dtype == np.float64 and q_s.ndim == 3 and q_s.shape[0] * q_s.shape[1] >= rotations._KERNEL_MIN_ROWS
            and q_matrix.shape == (q_s.shape[0], 4, 4) and np.isfinite(q_matrix).all()):
        before, after = np.empty(q_s.shape[:-1]), np.empty(q_s.shape[:-1])
        err_b, err_a = np.empty(q_s.shape[:-1] + (3,)), np.empty(q_s.shape[:-1] + (3,))
        if table is None:
            table = truth_table(np.ascontiguousarray(reference_rad, dtype=float)[None])[0]
        if channel_errors_cs(q_s, np.ascontiguousarray(q_matrix), table, rotations._LOCK_SIN, int(chan),
                             before, after, err_b, err_a) == 0:
            rotations._finite_angles(err_b, err_a)
            return before, after, {"before": err_b, "after": err_a}
    q_s = np.asarray(q_s, dtype=float)
    after = rotations.euler_zxy_unchecked(rotations.apply_quat_matrix_trusted(q_matrix, q_s))
    before = rotations.euler_zxy_unchecked(q_s)
    rotations._finite_angles(before, after)
    ref = np.asarray(reference_rad, dtype=float)
    return before[..., chan], after[..., chan], {"before": metrics.angle_difference_trusted(before, ref),
                                                 "after": metrics.angle_difference_trusted(after, ref)}


@jit
def _euler_errors_rows(q, table, out):
    """Per-sample :func:`euler_errors_cs` of q (n, 4) against table (n, 9) into out (n, 3) (tests)."""
    for i in range(q.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = table_errors(q[i, 0], q[i, 1], q[i, 2], q[i, 3], table[i])


@jit
def _euler_error_stats_serial(q, table, t, out_sum, out_sumsq, out_max):
    tr = table[t] if table.shape[0] > 1 else table[0]
    s0 = s1 = s2 = 0.0
    ss0 = ss1 = ss2 = 0.0
    m0, m1, m2 = out_max[t, 0], out_max[t, 1], out_max[t, 2]
    for i in range(q.shape[1]):
        e0, e1, e2 = table_errors(q[t, i, 0], q[t, i, 1], q[t, i, 2], q[t, i, 3], tr[i])
        s0 += e0
        s1 += e1
        s2 += e2
        ss0 += e0 * e0
        ss1 += e1 * e1
        ss2 += e2 * e2
        m0 = max(m0, abs(e0))
        m1 = max(m1, abs(e1))
        m2 = max(m2, abs(e2))
    out_sum[t, 0] += s0
    out_sum[t, 1] += s1
    out_sum[t, 2] += s2
    out_sumsq[t, 0] += ss0
    out_sumsq[t, 1] += ss1
    out_sumsq[t, 2] += ss2
    out_max[t, 0], out_max[t, 1], out_max[t, 2] = m0, m1, m2


@jit(parallel=True)
def _euler_error_stats_parallel(q, table, out_sum, out_sumsq, out_max):
    for t in prange(q.shape[0]):
        _euler_error_stats_serial(q, table, t, out_sum, out_sumsq, out_max)


def _euler_error_stats(q, truth, out_sum, out_sumsq, out_max) -> None:
    """Per-trial sums, sums of squares and maxima of wrapped Eq 8 errors (trials in parallel).

    ``truth`` is (Tt, n, 3) angles or (Tt, n, 9) a :func:`truth_table`."""
    table = truth if truth.shape[-1] == 9 else truth_table(truth)
    _euler_error_stats_parallel(q, table, out_sum, out_sumsq, out_max)


def progress_enabled() -> bool:
    """Whether to show a progress bar: never if ``MTCAL_PROGRESS=0``, else when interactive."""
    env = os.environ.get("MTCAL_PROGRESS")
    if env is not None:
        return env not in ("0", "false", "no", "")
    if os.environ.get("CI"):
        return False
    return bool(getattr(sys.stderr, "isatty", lambda: False)()) or "ipykernel" in sys.modules


def progress(iterable, total: int | None = None, desc: str = "Monte Carlo"):
    """Wrap ``iterable`` in a tqdm progress bar when :func:`progress_enabled`, else return it.

    Used by every Monte Carlo loop that can run longer than a few seconds; silent in
    CI, under nbval and in ``make reproduce`` (``MTCAL_PROGRESS=0``).

    >>> list(progress(range(3), desc="trials"))  # doctest: +SKIP
    [0, 1, 2]
    """
    if not progress_enabled():
        return iterable
    from tqdm.auto import tqdm

    return tqdm(iterable, total=total, desc=desc, leave=False)


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
