"""Attitude filters: QNCF (Wang2023), the RAMS EKF (Wang2022), baselines, an IMU-only Mahony,
and adapters to the anchor libraries (vqf, imufusion, ahrs) for the bake-off.

The public names of every submodule are re-exported here (see ``__all__``).
"""

from typing import TYPE_CHECKING

from mtcal.core.lazy import lazy_attributes

if TYPE_CHECKING:  # the eager imports, for type checkers and tests/test_import_graph.py
    from . import anchors, baselines, mahony, qncf, rams_ekf, registry
    from .qncf import amd_statistic, initial_attitude_from_accel, QncfFilter, QncfParams, QncfResult
    from .rams_ekf import (initial_state, measurement_model, RamsEkfFilter, RamsEkfParams, RamsEkfReference,
                           RamsEkfResult, run_rams_ekf)
    from .baselines import (accel_only_angle, angle_from_orientation, MagneticDisturbance, mahony_marg, MargGains,
                            simulate_magnetometer, triad_quaternion)
    from .mahony import mahony_imu, MahonyParams, MahonyResult
    from .registry import (AxisContext, available_filters, BUILTIN_FILTERS, builtin_filter_names, Deferred,
                           filter_names, FilterEntry, get_filter, RAMS_EKF_DEFAULT_GAIN, register_filter,
                           require_filter, unregister_filter)
    from .anchors import run_attitude_filter, run_axis_angle_filter, tilt_error_rad, twist_angle_rad

__all__ = ["qncf", "rams_ekf", "baselines", "mahony", "anchors", "QncfParams", "QncfResult", "QncfFilter",
           "amd_statistic", "initial_attitude_from_accel", "RamsEkfParams", "RamsEkfReference", "RamsEkfResult",
           "RamsEkfFilter", "run_rams_ekf", "measurement_model", "initial_state", "accel_only_angle",
           "MagneticDisturbance", "simulate_magnetometer", "mahony_marg", "MargGains", "angle_from_orientation",
           "triad_quaternion", "MahonyParams", "MahonyResult", "mahony_imu", "registry", "FilterEntry", "AxisContext",
           "Deferred", "BUILTIN_FILTERS", "builtin_filter_names", "register_filter", "unregister_filter", "get_filter", "filter_names", "available_filters", "require_filter",
           "RAMS_EKF_DEFAULT_GAIN", "run_attitude_filter", "run_axis_angle_filter", "tilt_error_rad", "twist_angle_rad"]

#: Submodules, loaded on first attribute access (``import mtcal`` stays light for the CLI).
_SUBMODULES = ('anchors', 'baselines', 'mahony', 'qncf', 'rams_ekf', 'registry')
#: Re-exported name → submodule defining it (imported on first access).
_EXPORTS = {
    "RAMS_EKF_DEFAULT_GAIN": "registry", "run_attitude_filter": "anchors", "run_axis_angle_filter": "anchors",
    "tilt_error_rad": "anchors", "twist_angle_rad": "anchors", "MagneticDisturbance": "baselines",
    "MargGains": "baselines", "accel_only_angle": "baselines", "angle_from_orientation": "baselines",
    "mahony_marg": "baselines", "simulate_magnetometer": "baselines", "triad_quaternion": "baselines",
    "MahonyParams": "mahony", "MahonyResult": "mahony", "mahony_imu": "mahony", "QncfFilter": "qncf",
    "QncfParams": "qncf", "QncfResult": "qncf", "amd_statistic": "qncf", "initial_attitude_from_accel": "qncf",
    "RamsEkfFilter": "rams_ekf", "RamsEkfParams": "rams_ekf", "RamsEkfReference": "rams_ekf",
    "RamsEkfResult": "rams_ekf", "initial_state": "rams_ekf", "measurement_model": "rams_ekf",
    "run_rams_ekf": "rams_ekf", "AxisContext": "registry", "FilterEntry": "registry", "Deferred": "registry",
    "BUILTIN_FILTERS": "registry", "builtin_filter_names": "registry",
    "available_filters": "registry", "filter_names": "registry", "get_filter": "registry",
    "register_filter": "registry", "require_filter": "registry", "unregister_filter": "registry",
}

__getattr__, __dir__ = lazy_attributes(globals(), _SUBMODULES, _EXPORTS)
