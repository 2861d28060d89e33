"""Paper-independent core: conventions, simulation, motion profiles, metrics, Monte Carlo, validation.

Nothing here names a paper. Radians and SI units throughout.

The public names of every submodule are re-exported here (see ``__all__``).
"""

from typing import TYPE_CHECKING

from . import compiled  # first: numba's settings are made there before numba loads
from .lazy import lazy_attributes

if TYPE_CHECKING:  # the eager imports, for type checkers and tests/test_import_graph.py
    from . import compiled  # first: numba's settings are made there before numba loads
    from . import metrics, montecarlo, profiles, rng, rotations, sensor_grades, simulate, units, validate
    from .rotations import (align_signs, axis_angle_matrix, coupling_error_eq4, dcm_zyx, euler_zxy_from_quat,
                            euler_zxy_unchecked, GIMBAL_LOCK_COS, hamilton, installation_angles,
                            installation_angles_from_mount, installation_matrix, installation_matrix_small_angle,
                            left_matrix, make_continuous, mount_quaternion, pitch_roll_from_specific_force,
                            quat_angle_between, quat_conjugate, quat_from_euler_zxy, quat_from_matrix, quat_from_rotvec,
                            quat_multiply, quat_normalize, quat_to_matrix, relative_to_initial, right_matrix,
                            rotvec_from_quat, specific_force_zyx, wrap_angle)
    from .simulate import (apply_sensor_errors, body_rates, GRAVITY_W_M_S2, ImuErrorModel, ImuRecord, ImuStream,
                           integrate_gyro, SensorErrors, simulate_imu, specific_force, Trajectory)
    from .profiles import (AngleProfile, constant_rate, fixed_axis_trajectory, sinusoid, step_schedule,
                           trajectory_from_euler_zxy)
    from .metrics import (allan_deviation, angle_difference, bootstrap_medians, fit_allan_noise, max_abs_error,
                          percentile_band, rmse, split_static_moving)
    from .montecarlo import ChunkConsumer, ErrorAccumulator, progress, progress_enabled, run_streaming
    from .validate import (angle_pair_deg, angle_rad, as_float_array, check_accel_units, check_gyro_units, choice,
                           MAX_GYRO_RAD_S, MAX_SAMPLE_INTERVAL_S, merge_parameters, number_in_range, positive_int,
                           positive_scalar, same_leading_shape, sample_interval, time_vector, unit_quaternion)
    from .units import ARCSEC, DEG, DEG_H, DEG_RT_H, DEG_S, G, MG, STANDARD_GRAVITY_M_S2, UG
    from .sensor_grades import grade_names, GRADES, sensor_grade, SensorGrade
    from .rng import stream_key, stream_rng, trial_rng
    from .compiled import component_major, jit

__all__ = ["rotations", "simulate", "profiles", "metrics", "montecarlo", "validate", "units", "sensor_grades", "rng",
           "compiled", "mount_quaternion", "relative_to_initial", "installation_angles",
           "installation_angles_from_mount", "GIMBAL_LOCK_COS", "hamilton", "quat_multiply", "quat_conjugate",
           "quat_normalize", "left_matrix", "right_matrix", "align_signs", "make_continuous", "quat_from_rotvec",
           "rotvec_from_quat", "quat_from_euler_zxy", "euler_zxy_from_quat", "euler_zxy_unchecked", "quat_to_matrix",
           "quat_from_matrix", "installation_matrix", "installation_matrix_small_angle", "coupling_error_eq4",
           "dcm_zyx", "specific_force_zyx", "pitch_roll_from_specific_force", "axis_angle_matrix", "wrap_angle",
           "quat_angle_between", "Trajectory", "SensorErrors", "ImuErrorModel", "ImuRecord", "ImuStream",
           "body_rates", "specific_force", "simulate_imu", "apply_sensor_errors", "integrate_gyro", "GRAVITY_W_M_S2",
           "AngleProfile", "step_schedule", "sinusoid", "constant_rate", "trajectory_from_euler_zxy",
           "fixed_axis_trajectory", "angle_difference", "rmse", "max_abs_error", "split_static_moving",
           "allan_deviation", "fit_allan_noise", "percentile_band", "bootstrap_medians", "progress", "ChunkConsumer",
           "ErrorAccumulator", "run_streaming", "progress_enabled", "STANDARD_GRAVITY_M_S2", "as_float_array",
           "positive_scalar", "positive_int", "time_vector", "angle_rad", "unit_quaternion", "same_leading_shape",
           "MAX_GYRO_RAD_S", "check_gyro_units", "check_accel_units", "number_in_range", "angle_pair_deg", "choice",
           "merge_parameters", "sample_interval", "MAX_SAMPLE_INTERVAL_S", "DEG", "DEG_S", "DEG_H", "DEG_RT_H",
           "ARCSEC", "G", "MG", "UG", "SensorGrade", "GRADES", "sensor_grade", "grade_names", "stream_key",
           "trial_rng", "stream_rng", "jit", "component_major"]

#: Submodules, loaded on first attribute access (``import mtcal`` stays light for the CLI).
_SUBMODULES = ("metrics", "montecarlo", "profiles", "rng", "rotations", "sensor_grades", "simulate", "units",
               "validate")
#: Re-exported name → submodule defining it (imported on first access).
_EXPORTS = {
    "component_major": "compiled", "jit": "compiled", "allan_deviation": "metrics", "angle_difference": "metrics",
    "bootstrap_medians": "metrics", "fit_allan_noise": "metrics", "max_abs_error": "metrics",
    "percentile_band": "metrics", "rmse": "metrics", "split_static_moving": "metrics", "ChunkConsumer": "montecarlo",
    "ErrorAccumulator": "montecarlo", "progress": "montecarlo", "progress_enabled": "montecarlo",
    "run_streaming": "montecarlo", "AngleProfile": "profiles", "constant_rate": "profiles",
    "fixed_axis_trajectory": "profiles", "sinusoid": "profiles", "step_schedule": "profiles",
    "trajectory_from_euler_zxy": "profiles", "stream_key": "rng", "stream_rng": "rng", "trial_rng": "rng",
    "GIMBAL_LOCK_COS": "rotations", "align_signs": "rotations", "axis_angle_matrix": "rotations",
    "coupling_error_eq4": "rotations", "dcm_zyx": "rotations", "euler_zxy_from_quat": "rotations",
    "euler_zxy_unchecked": "rotations", "hamilton": "rotations", "installation_angles": "rotations",
    "installation_angles_from_mount": "rotations", "installation_matrix": "rotations",
    "installation_matrix_small_angle": "rotations", "left_matrix": "rotations", "make_continuous": "rotations",
    "mount_quaternion": "rotations", "pitch_roll_from_specific_force": "rotations",
    "quat_angle_between": "rotations", "quat_conjugate": "rotations", "quat_from_euler_zxy": "rotations",
    "quat_from_matrix": "rotations", "quat_from_rotvec": "rotations", "quat_multiply": "rotations",
    "quat_normalize": "rotations", "quat_to_matrix": "rotations", "relative_to_initial": "rotations",
    "right_matrix": "rotations", "rotvec_from_quat": "rotations", "specific_force_zyx": "rotations",
    "wrap_angle": "rotations", "GRADES": "sensor_grades", "SensorGrade": "sensor_grades",
    "grade_names": "sensor_grades", "sensor_grade": "sensor_grades", "GRAVITY_W_M_S2": "simulate",
    "ImuErrorModel": "simulate", "ImuRecord": "simulate", "ImuStream": "simulate", "SensorErrors": "simulate",
    "Trajectory": "simulate", "apply_sensor_errors": "simulate", "body_rates": "simulate",
    "integrate_gyro": "simulate", "simulate_imu": "simulate", "specific_force": "simulate", "ARCSEC": "units",
    "DEG": "units", "DEG_H": "units", "DEG_RT_H": "units", "DEG_S": "units", "G": "units", "MG": "units",
    "STANDARD_GRAVITY_M_S2": "units", "UG": "units", "MAX_GYRO_RAD_S": "validate",
    "MAX_SAMPLE_INTERVAL_S": "validate", "angle_pair_deg": "validate", "angle_rad": "validate",
    "as_float_array": "validate", "check_accel_units": "validate", "check_gyro_units": "validate",
    "choice": "validate", "merge_parameters": "validate", "number_in_range": "validate", "positive_int": "validate",
    "positive_scalar": "validate", "same_leading_shape": "validate", "sample_interval": "validate",
    "time_vector": "validate", "unit_quaternion": "validate",
}

__getattr__, __dir__ = lazy_attributes(globals(), _SUBMODULES, _EXPORTS)
