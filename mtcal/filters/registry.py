"""Filter registry: one registration per filter makes it available to the bake-off, the sweep and the anchors.

Each entry (:class:`FilterEntry`) says what the filter is, whether it is one of
mtcal's own filters (``"ours"``) or an open-source anchor (``"anchor"``: vqf,
imufusion, ahrs), its one tuned gain (default and unit), and how to run it on a
batch of records:

* ``output="attitude"`` — ``run(gyro_rad_s, accel_m_s2, dt_s, gain, q0) -> q_ws``
  with ``gyro_rad_s``, ``accel_m_s2`` of shape (T, N, 3) (T trials of N samples; rad/s,
  m/s², gyro sample k over ``[t_k, t_{k+1}]``), ``dt_s`` (s), ``gain`` (> 0) and ``q0``
  (T, 4); returns the scalar-first sensor → world (z up) attitude at each ``t_k``, (T, N, 4).
  A runner trusts its inputs: :func:`mtcal.filters.anchors.run_attitude_filter` checks them
  once (finite float64, units, ``dt_s`` and ``gain`` > 0, unit ``q0``).
* ``output="angle"`` — ``run(gyro_rad_s, accel_m_s2, dt_s, gain, context) -> theta_rad``
  (T, N): the angle about a known axis (a movable surface), where ``context`` is an
  :class:`AxisContext` (axis, rest flags, initial specific force, sensor noise).

Consumers look filters up here and never by name: :func:`mtcal.filters.anchors.run_attitude_filter`,
the sweep evaluators (``attitude`` takes every attitude filter, ``surface`` every
filter), :mod:`mtcal.sweep.bakeoff` (angle filters join the surface family) and the
``mtcal attitude --filter`` choices.

mtcal's built-in filters are declared in one place, :data:`BUILTIN_FILTERS` below: each
entry names its runner by module and function (:class:`Deferred`), imported on the
runner's first call, so no module registers anything by being imported and listing the
filters imports none of them. Adding a built-in filter is one entry in that table; a
notebook or a test adds its own with :func:`register_filter`.

References
----------
wang2023cja (QNCF, Eq 5–9); wang2022sensors (RAMS EKF, Sec. 4); ``docs/study_template.md``
(what a new filter touches).

Examples
--------
>>> import numpy as np
>>> def still(gyro_rad_s, accel_m_s2, dt_s, gain, q0):
...     return np.broadcast_to(q0[:, None, :], gyro_rad_s.shape[:2] + (4,)).copy()
>>> _ = register_filter("still", still, output="attitude", default_gain=1.0, gain_unit="none (1)",
...                     origin="ours", description="holds its initial attitude")
>>> "still" in filter_names(output="attitude"), get_filter("still").default_gain
(True, 1.0)
>>> unregister_filter("still")
>>> "still" in filter_names()
False
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["FilterEntry", "AxisContext", "Deferred", "BUILTIN_FILTERS", "register_filter", "unregister_filter",
           "get_filter", "filter_names", "builtin_filter_names", "available_filters", "require_filter", "OUTPUTS",
           "ORIGINS", "RAMS_EKF_DEFAULT_GAIN"]

#: What a filter returns: an attitude quaternion, or an angle about a known axis.
OUTPUTS = ("attitude", "angle")
#: ``"ours"`` = implemented in mtcal; ``"anchor"`` = an open-source library adapted for comparison.
ORIGINS = ("ours", "anchor")

#: Default of the RAMS EKF's tuned value, σa,moving (m/s²).
RAMS_EKF_DEFAULT_GAIN = 2.0


@dataclass(frozen=True)
class Deferred:
    """A runner named by its module and function, imported on its first call.

    Calling it calls ``module.function`` with the same arguments; the declaration itself
    imports nothing (the table of built-in filters stays light, and the module that
    defines a runner does not register it).

    Examples
    --------
    >>> norm = Deferred("numpy.linalg", "norm")
    >>> float(norm([3.0, 4.0]))
    5.0
    """

    module: str
    function: str

    def resolve(self) -> Callable:
        """The named function (imports ``module``)."""
        return getattr(importlib.import_module(self.module), self.function)

    def __call__(self, *args, **kwargs):
        return self.resolve()(*args, **kwargs)


@dataclass(frozen=True)
class AxisContext:
    """What an angle-about-axis filter may use besides the records (batch of T trials of N samples).

    Parameters
    ----------
    axis_s : ndarray, shape (3,)
        Unit rotation axis in the sensor frame.
    is_static : ndarray of bool, shape (T, N)
        Rest flags (zero-velocity input).
    a0_m_s2 : ndarray, shape (T, 3)
        Specific force at the reference rest (m/s²).
    gyro_noise_rad_s_rt_hz, accel_noise_m_s2_rt_hz : float
        White-noise densities of the sensors (rad/s/√Hz, m/s²/√Hz).
    init : slice or None
        The reference rest (samples) an angle filter may initialise from (``None``:
        the first ``init_samples`` samples).
    rests : tuple of slice
        Later rests (e.g. restart points after gyro clipping).
    """

    axis_s: np.ndarray
    is_static: np.ndarray
    a0_m_s2: np.ndarray
    gyro_noise_rad_s_rt_hz: float
    accel_noise_m_s2_rt_hz: float
    init: slice | None = None
    rests: tuple = ()


@dataclass(frozen=True)
class FilterEntry:
    """One registered filter (see the module doc for ``run``'s signature per ``output``).

    Parameters
    ----------
    name : str
        Registry key (also the metric prefix in sweeps, ``<name>.<metric>``).
    run : callable
        The runner.
    output : {"attitude", "angle"}
    default_gain : float
        Default of the one tuned gain (> 0).
    gain_unit : str
        What the gain is, with its unit (``"K_p (1/s)"``).
    origin : {"ours", "anchor"}
    description : str
        One line for listings.
    requires : str or None
        Optional Python package the runner imports (``None`` = always available).
    reference : callable or None
        For an anchor that ``run`` computes with mtcal's compiled equivalent of the library's
        per-sample loop: the library's own runner (same signature as ``run``), kept to check
        their equality on a subset (:func:`mtcal.filters.anchors.reference_difference`).
    """

    name: str
    run: Callable
    output: str
    default_gain: float
    gain_unit: str
    origin: str
    description: str = ""
    requires: str | None = None
    reference: Callable | None = None


#: mtcal's built-in filters, in listing order: the one declaration of every filter the bake-off, the
#: sweep, the anchors and the CLI see (runners in :mod:`mtcal.filters.anchors`; the RAMS EKF entry runs
#: the ``mtcal angle`` system, :mod:`mtcal.systems.surface_angle`: ZVD-switched EKF from the reference
#: rest, restart after gyro clipping).
BUILTIN_FILTERS = (
    FilterEntry("qncf", Deferred("mtcal.filters.anchors", "_qncf"), "attitude", 1.0, "K_p (1/s)", "ours",
                "quaternion nonlinear complementary filter (wang2023cja Eq 5-9), K_i = K_p / 50 s"),
    FilterEntry("mahony", Deferred("mtcal.filters.anchors", "_mahony"), "attitude", 1.0, "K_p (1/s)", "ours",
                "IMU-only Mahony explicit complementary filter, K_i = K_p / 50 s"),
    FilterEntry("madgwick", Deferred("mtcal.filters.anchors", "_madgwick_batch"), "attitude", 0.033, "beta (rad/s)",
                "anchor", "ahrs.filters.Madgwick (gradient descent), inputs delayed one sample; "
                          "compiled equivalent (xio_ahrs), ahrs itself as the reference",
                requires="ahrs", reference=Deferred("mtcal.filters.anchors", "_madgwick_ahrs_batch")),
    FilterEntry("vqf", Deferred("mtcal.filters.anchors", "_vqf_batch"), "attitude", 3.0, "tau_acc (s)", "anchor",
                "vqf.VQF 6D (Laidig & Seel 2023), gyro delayed one sample", requires="vqf"),
    FilterEntry("fusion", Deferred("mtcal.filters.anchors", "_fusion_batch"), "attitude", 0.5, "gain (1)", "anchor",
                "imufusion.Ahrs (x-io Fusion), NWU, °/s and g", requires="imufusion"),
    FilterEntry("rams_ekf", Deferred("mtcal.systems.surface_angle", "_registered_rams_ekf"), "angle",
                RAMS_EKF_DEFAULT_GAIN, "sigma_a_moving (m/s²)", "ours",
                "RAMS EKF as the wang2022sensors study runs it (batched): angle about a known axis, ZVD "
                "switching, restart after clipping (wang2022sensors Sec. 4)"),
)
_REGISTRY: dict[str, FilterEntry] = {e.name: e for e in BUILTIN_FILTERS}


def register_filter(name: str, run: Callable, *, output: str, default_gain: float, gain_unit: str, origin: str,
                    description: str = "", requires: str | None = None, reference: Callable | None = None,
                    replace: bool = False) -> FilterEntry:
    """Register a filter; returns its :class:`FilterEntry`.

    Raises
    ------
    ValueError
        Empty/duplicate name (unless ``replace``), unknown ``output``/``origin``, gain ≤ 0.
    TypeError
        ``run`` (or a given ``reference``) not callable.
    """
    if not isinstance(name, str) or not name or "." in name:
        raise ValueError(f"filter name must be a non-empty str without '.', got {name!r}")
    if name in _REGISTRY and not replace:
        raise ValueError(f"filter {name!r} is already registered (pass replace=True)")
    if not callable(run):
        raise TypeError(f"run must be callable, got {type(run).__name__}")
    if reference is not None and not callable(reference):
        raise TypeError(f"reference must be callable or None, got {type(reference).__name__}")
    if output not in OUTPUTS:
        raise ValueError(f"output must be one of {list(OUTPUTS)}, got {output!r}")
    if origin not in ORIGINS:
        raise ValueError(f"origin must be one of {list(ORIGINS)}, got {origin!r}")
    if isinstance(default_gain, bool) or not isinstance(default_gain, (int, float)) or not default_gain > 0:
        raise ValueError(f"default_gain must be a number > 0, got {default_gain!r}")
    entry = FilterEntry(name, run, output, float(default_gain), str(gain_unit), origin, description, requires,
                        reference)
    _REGISTRY[name] = entry
    return entry


def unregister_filter(name: str) -> None:
    """Remove a registered filter (tests, notebooks trying a variant); ValueError if unknown."""
    if name not in _REGISTRY:
        raise ValueError(f"filter must be one of {sorted(_REGISTRY)}, got {name!r}")
    del _REGISTRY[name]


def filter_names(*, output: str | None = None, origin: str | None = None) -> list[str]:
    """Registered names in registration order, optionally only one ``output`` / ``origin``."""
    return _names(_REGISTRY.values(), output, origin)


def builtin_filter_names(*, output: str | None = None, origin: str | None = None) -> list[str]:
    """Names declared in :data:`BUILTIN_FILTERS`, whatever a session registered or removed since.

    For defaults that must not depend on the session (the bake-off's filters).

    Examples
    --------
    >>> builtin_filter_names(output="attitude")
    ['qncf', 'mahony', 'madgwick', 'vqf', 'fusion']
    """
    return _names(BUILTIN_FILTERS, output, origin)


def _names(entries, output: str | None, origin: str | None) -> list[str]:
    if output is not None and output not in OUTPUTS:
        raise ValueError(f"output must be one of {list(OUTPUTS)}, got {output!r}")
    if origin is not None and origin not in ORIGINS:
        raise ValueError(f"origin must be one of {list(ORIGINS)}, got {origin!r}")
    return [e.name for e in entries if (output is None or e.output == output)
            and (origin is None or e.origin == origin)]


def get_filter(name: str) -> FilterEntry:
    """The entry registered as ``name`` (ValueError listing the valid names)."""
    if not isinstance(name, str) or name not in _REGISTRY:
        raise ValueError(f"filter must be one of {list(_REGISTRY)}, got {name!r}")
    return _REGISTRY[name]


def require_filter(name: str):
    """Import the optional package behind ``name`` (None when it needs none); ImportError with a clear message."""
    entry = get_filter(name)
    if entry.requires is None:
        return None
    try:
        return importlib.import_module(entry.requires)
    except ImportError as exc:
        raise ImportError(f"filter {name!r} needs the optional package {entry.requires!r} "
                          f"(pip install 'mtcal[bench]'): {exc}") from None


def available_filters(*, output: str | None = None) -> list[str]:
    """Registered filters whose optional package imports (mtcal's own always)."""
    out = []
    for name in filter_names(output=output):
        try:
            require_filter(name)
        except ImportError:
            continue
        out.append(name)
    return out
