"""Attitude filters: QNCF (Wang2023), the RAMS EKF (Wang2022), baselines, an IMU-only Mahony,
and adapters to the anchor libraries (vqf, imufusion, ahrs) for the bake-off.

The public names of every submodule are re-exported here (see ``__all__``).
"""

from . import anchors, baselines, mahony, qncf, rams_ekf, registry
from .qncf import amd_statistic, initial_attitude_from_accel, QncfFilter, QncfParams, QncfResult
from .rams_ekf import (initial_state, measurement_model, RamsEkfFilter, RamsEkfParams, RamsEkfReference,
                       RamsEkfResult, run_rams_ekf)
from .baselines import (accel_only_angle, angle_from_orientation, MagneticDisturbance, mahony_marg, MargGains,
                        simulate_magnetometer, triad_quaternion)
from .mahony import mahony_imu, MahonyParams, MahonyResult
from .registry import (AxisContext, available_filters, filter_names, FilterEntry, get_filter, register_filter,
                       require_filter, unregister_filter)
from .anchors import RAMS_EKF_DEFAULT_GAIN, run_attitude_filter, run_axis_angle_filter, tilt_error_rad, twist_angle_rad

__all__ = ["qncf", "rams_ekf", "baselines", "mahony", "anchors", "QncfParams", "QncfResult", "QncfFilter",
           "amd_statistic", "initial_attitude_from_accel", "RamsEkfParams", "RamsEkfReference", "RamsEkfResult",
           "RamsEkfFilter", "run_rams_ekf", "measurement_model", "initial_state", "accel_only_angle",
           "MagneticDisturbance", "simulate_magnetometer", "mahony_marg", "MargGains", "angle_from_orientation",
           "triad_quaternion", "MahonyParams", "MahonyResult", "mahony_imu", "registry", "FilterEntry", "AxisContext",
           "register_filter", "unregister_filter", "get_filter", "filter_names", "available_filters", "require_filter",
           "RAMS_EKF_DEFAULT_GAIN", "run_attitude_filter", "run_axis_angle_filter", "tilt_error_rad", "twist_angle_rad"]
