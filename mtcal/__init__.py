"""mtcal — attitude estimation and IMU calibration, reproduced from three papers.

Layers (each a subpackage, imports only point downwards):

* :mod:`mtcal.core` — paper-independent: rotations and conventions, IMU simulation,
  motion profiles, metrics, streaming Monte Carlo, input validation
* :mod:`mtcal.methods` — methods named by what they compute (least-squares error
  quaternion, constrained fits, six-position procedure, large-angle accelerometer
  attitude, gyro roll, rotation axis, zero-velocity detection)
* :mod:`mtcal.filters` — QNCF, RAMS EKF, baselines
* :mod:`mtcal.systems` — the measurement systems (installation calibration, surface angle,
  attitude, plausibility of a log): what the notebooks, the sweeps and the CLI all call
* :mod:`mtcal.reporting` — the papers' numbers, comparison with bands, output files
  (imports only ``core``; the studies build their comparison rows with it)
* :mod:`mtcal.studies` — one package per paper: ``wang2023cja``, ``tan2022``,
  ``wang2022sensors``
* :mod:`mtcal.sweep` — parameter sweeps (trade studies) on local cores or a Dask cluster
* :mod:`mtcal.runs` — notebook execution, what-if runs and their comparison (tooling, not in
  ``__all__``: ``import mtcal.runs``)
* :mod:`mtcal.cli` — the ``mtcal`` command (not in ``__all__``: run ``mtcal``, or ``import mtcal.cli``)

Order, lowest first: core < methods < filters < systems < reporting < studies < sweep <
runs < cli (``tests/test_import_graph.py`` checks it and that no import cycle exists).
Every layer and re-exported name is loaded on first use, not by ``import mtcal`` (a CLI call
stays light: numba, scipy and pandas load only when a command needs them).

The most used names are re-exported here:

>>> import numpy as np, mtcal
>>> q = mtcal.quat_from_euler_zxy(0.1, 0.2, 0.3)
>>> np.round(mtcal.euler_zxy_from_quat(q), 12).tolist()
[0.1, 0.2, 0.3]
"""

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the eager imports, for type checkers and tests/test_import_graph.py
    from mtcal import core, filters, methods, reporting, systems
    from mtcal.core.metrics import angle_difference, max_abs_error, percentile_band, rmse
    from mtcal.core.rotations import (euler_zxy_from_quat, quat_conjugate, quat_from_euler_zxy, quat_multiply,
                                      quat_to_matrix)
    from mtcal.core.simulate import ImuErrorModel, ImuRecord, ImuStream, SensorErrors, Trajectory, simulate_imu
    from mtcal.filters.qncf import QncfFilter, QncfParams, qncf
    from mtcal.filters.rams_ekf import RamsEkfFilter, RamsEkfParams, run_rams_ekf
    from mtcal.methods.quaternion_lsq import apply_error_matrix, least_squares_error_matrix
    from mtcal.methods.rotation_axis import estimate_axis
    from mtcal.methods.zero_velocity import ZvdParams, detect_static
    from mtcal.reporting.paper_numbers import load as load_paper_table

from mtcal import core  # light: numba's settings (mtcal.core.compiled); every submodule loads on first use

__version__ = "0.2.0"

__all__ = [
    "core", "methods", "filters", "systems", "reporting", "studies", "sweep",
    "quat_from_euler_zxy", "euler_zxy_from_quat", "quat_multiply", "quat_conjugate", "quat_to_matrix",
    "Trajectory", "SensorErrors", "ImuErrorModel", "ImuRecord", "ImuStream", "simulate_imu",
    "angle_difference", "rmse", "max_abs_error", "percentile_band",
    "QncfParams", "QncfFilter", "qncf", "RamsEkfParams", "RamsEkfFilter", "run_rams_ekf",
    "least_squares_error_matrix", "apply_error_matrix", "estimate_axis", "ZvdParams", "detect_static",
    "load_paper_table", "__version__",
]


#: Re-exported name → module defining it, imported on first access, so that ``import mtcal``
#: (and a CLI call) loads neither numba, scipy nor pandas until a name needs them.
_EXPORTS = {
    "angle_difference": "mtcal.core.metrics", "max_abs_error": "mtcal.core.metrics",
    "percentile_band": "mtcal.core.metrics", "rmse": "mtcal.core.metrics",
    "euler_zxy_from_quat": "mtcal.core.rotations", "quat_conjugate": "mtcal.core.rotations",
    "quat_from_euler_zxy": "mtcal.core.rotations", "quat_multiply": "mtcal.core.rotations",
    "quat_to_matrix": "mtcal.core.rotations",
    "ImuErrorModel": "mtcal.core.simulate", "ImuRecord": "mtcal.core.simulate", "ImuStream": "mtcal.core.simulate",
    "SensorErrors": "mtcal.core.simulate", "Trajectory": "mtcal.core.simulate", "simulate_imu": "mtcal.core.simulate",
    "QncfFilter": "mtcal.filters.qncf", "QncfParams": "mtcal.filters.qncf", "qncf": "mtcal.filters.qncf",
    "RamsEkfFilter": "mtcal.filters.rams_ekf", "RamsEkfParams": "mtcal.filters.rams_ekf",
    "run_rams_ekf": "mtcal.filters.rams_ekf",
    "apply_error_matrix": "mtcal.methods.quaternion_lsq", "least_squares_error_matrix": "mtcal.methods.quaternion_lsq",
    "estimate_axis": "mtcal.methods.rotation_axis",
    "ZvdParams": "mtcal.methods.zero_velocity", "detect_static": "mtcal.methods.zero_velocity",
}
_RENAMED = {"load_paper_table": ("mtcal.reporting.paper_numbers", "load")}


def __getattr__(name):  # lazy: layers and re-exported names load on first use
    if name in ("methods", "filters", "systems", "reporting", "studies", "sweep", "runs", "cli"):
        return importlib.import_module(f"mtcal.{name}")
    if name in _EXPORTS or name in _RENAMED:
        module, attr = _RENAMED.get(name, (_EXPORTS.get(name), name))
        value = getattr(importlib.import_module(module), attr)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'mtcal' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
