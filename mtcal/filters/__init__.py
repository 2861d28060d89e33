"""Attitude filters: QNCF (Wang2023), the RAMS EKF (Wang2022), baselines, an IMU-only Mahony,
and adapters to the anchor libraries (vqf, imufusion, ahrs) for the bake-off.

The public names of every submodule are re-exported here (see ``__all__``).
"""

from . import anchors, baselines, mahony, qncf, rams_ekf
from .qncf import amd_statistic, initial_attitude_from_accel, QncfFilter, QncfParams, QncfResult
from .rams_ekf import (initial_state, measurement_model, RamsEkfFilter, RamsEkfParams, RamsEkfReference,
                       RamsEkfResult, run_rams_ekf)
from .baselines import (accel_only_angle, angle_from_orientation, MagneticDisturbance, mahony_marg, MargGains,
                        simulate_magnetometer, triad_quaternion)
from .mahony import mahony_imu, MahonyParams, MahonyResult
from .anchors import (available_filters, DEFAULT_GAINS, FILTER_NAMES, GAIN_UNITS, require_filter, run_attitude_filter,
                      tilt_error_rad, twist_angle_rad)

__all__ = ["qncf", "rams_ekf", "baselines", "mahony", "anchors", "QncfParams", "QncfResult", "QncfFilter",
           "amd_statistic", "initial_attitude_from_accel", "RamsEkfParams", "RamsEkfReference", "RamsEkfResult",
           "RamsEkfFilter", "run_rams_ekf", "measurement_model", "initial_state", "accel_only_angle",
           "MagneticDisturbance", "simulate_magnetometer", "mahony_marg", "MargGains", "angle_from_orientation",
           "triad_quaternion", "MahonyParams", "MahonyResult", "mahony_imu", "FILTER_NAMES", "DEFAULT_GAINS",
           "GAIN_UNITS", "available_filters", "require_filter", "run_attitude_filter", "tilt_error_rad",
           "twist_angle_rad"]
