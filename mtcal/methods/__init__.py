"""Methods, named by what they compute (each cites the paper equation it implements).

* :mod:`~mtcal.methods.quaternion_lsq` — least-squares error quaternion matrix (Wang2023 Eq 10–14)
* :mod:`~mtcal.methods.constrained_fit` — SO(4) and 3-DOF mounting fits (beyond the papers)
* :mod:`~mtcal.methods.six_position` — six-position calibration procedure (Wang2023 §3.2)
* :mod:`~mtcal.methods.large_angle` — large-angle accelerometer pitch/roll, preset rotation (Tan2022 Eq 2–10)
* :mod:`~mtcal.methods.gyro_roll` — gyro roll decoupling, projection, hybrid (Tan2022 Eq 5, 12–14)
* :mod:`~mtcal.methods.rotation_axis` — rotation axis from three rests (Wang2022 Algorithm A1)
* :mod:`~mtcal.methods.zero_velocity` — zero-velocity (rest) detection (Wang2022 Table 1)
* :mod:`~mtcal.methods.rest_detection` — rest detection with levels measured from the data (any sensor)

The public names of every submodule are re-exported here (see ``__all__``).
"""

from typing import TYPE_CHECKING

from mtcal.core.lazy import lazy_attributes

if TYPE_CHECKING:  # the eager imports, for type checkers and tests/test_import_graph.py
    from . import (constrained_fit, gyro_roll, large_angle, quaternion_lsq, rest_detection, rotation_axis, six_position,
                   zero_velocity)
    from .quaternion_lsq import align_pairs, apply_error_matrix, least_squares_error_matrix
    from .constrained_fit import (associate_matrix, CalibrationScenario, distance_to_orthogonal, factor_so4,
                                  fit_mounting,
                                  fit_so4, METHODS, MIN_POSITIONS, mounting_error_matrix, MountingFit, project_to_so4,
                                  random_layout_rad, simulate_calibration_errors, so4_error_matrix,
                                  so4_from_quaternions,
                                  So4Fit, So4Projection, symmetric_layout_rad)
    from .six_position import (find_rests, match_rests, mean_quaternion, middle_slices, rest_attitudes, rest_means,
                               schedule_profile, six_positions_rad, stillness_from_gyro, stillness_from_quaternions)
    from .large_angle import (bias_moment_matrix, LAMBDA1_RAD, LAMBDA2_RAD, monte_carlo_pitch_errors, perturbed_errors,
                              perturbed_preset_pitch_error, pitch_error_eq10, pitch_error_eq3_printed, pitch_error_eq8,
                              pitch_error_first_order, pitch_roll_eq2, pitch_roll_from_preset_triad, preset_lambda,
                              preset_matrix, preset_specific_force, rms_pitch_error_from_moments, roll_error_eq4,
                              select_preset_pitch)
    from .gyro_roll import (body_rates_two_dof, euler_differential, loglog_slope, MAX_RATE_RAD_S, pitch_rate_magnitude,
                            projection_roll_error_eq14, projection_roll_error_exact, roll_decoupled_integration,
                            roll_hybrid, roll_hybrid_rmse_sweep, roll_projection, simulate_two_dof_imu,
                            two_dof_trajectory)
    from .rotation_axis import (angle_between, apply_sign_convention, axis_elevation, axis_error_std, axis_from_means,
                                AxisEstimator, AxisPlaneFit, AxisResult, distinct_positions, estimate_axis,
                                fit_axis_plane, gravity_change_norm)
    from .zero_velocity import detect_static, moving_variance, rest_intervals, ZvdParams
    from .rest_detection import detect_rests, paper_rest_report, RejectedRest, RestDetectorParams, RestReport

__all__ = ["quaternion_lsq", "constrained_fit", "six_position", "large_angle", "gyro_roll", "rotation_axis",
           "zero_velocity", "rest_detection", "least_squares_error_matrix", "apply_error_matrix", "align_pairs",
           "MIN_POSITIONS", "so4_from_quaternions", "associate_matrix", "factor_so4", "project_to_so4",
           "distance_to_orthogonal", "so4_error_matrix", "fit_so4", "mounting_error_matrix", "fit_mounting", "So4Fit",
           "MountingFit", "So4Projection", "CalibrationScenario", "symmetric_layout_rad", "random_layout_rad",
           "simulate_calibration_errors", "METHODS", "six_positions_rad", "schedule_profile", "stillness_from_gyro",
           "stillness_from_quaternions", "find_rests", "middle_slices", "mean_quaternion", "rest_means",
           "match_rests", "rest_attitudes", "LAMBDA1_RAD", "LAMBDA2_RAD", "pitch_roll_eq2",
           "pitch_error_first_order", "pitch_error_eq3_printed", "pitch_error_eq8", "roll_error_eq4", "preset_lambda",
           "pitch_error_eq10", "preset_matrix", "preset_specific_force", "pitch_roll_from_preset_triad",
           "select_preset_pitch", "perturbed_errors", "perturbed_preset_pitch_error", "monte_carlo_pitch_errors",
           "bias_moment_matrix", "rms_pitch_error_from_moments", "MAX_RATE_RAD_S", "body_rates_two_dof",
           "two_dof_trajectory", "simulate_two_dof_imu", "euler_differential", "roll_decoupled_integration",
           "roll_projection", "pitch_rate_magnitude", "roll_hybrid", "roll_hybrid_rmse_sweep",
           "projection_roll_error_eq14", "projection_roll_error_exact", "loglog_slope", "axis_from_means",
           "apply_sign_convention", "axis_elevation", "angle_between", "AxisEstimator", "AxisResult", "estimate_axis",
           "axis_error_std", "gravity_change_norm", "distinct_positions", "AxisPlaneFit", "fit_axis_plane",
           "ZvdParams", "moving_variance", "detect_static", "rest_intervals", "RestDetectorParams", "RestReport",
           "RejectedRest", "detect_rests", "paper_rest_report"]

#: Submodules, loaded on first attribute access (``import mtcal`` stays light for the CLI).
_SUBMODULES = ("constrained_fit", "gyro_roll", "large_angle", "quaternion_lsq", "rest_detection", "rotation_axis",
               "six_position", "zero_velocity")
#: Re-exported name → submodule defining it (imported on first access).
_EXPORTS = {
    "CalibrationScenario": "constrained_fit", "METHODS": "constrained_fit", "MIN_POSITIONS": "constrained_fit",
    "MountingFit": "constrained_fit", "So4Fit": "constrained_fit", "So4Projection": "constrained_fit",
    "associate_matrix": "constrained_fit", "distance_to_orthogonal": "constrained_fit",
    "factor_so4": "constrained_fit", "fit_mounting": "constrained_fit", "fit_so4": "constrained_fit",
    "mounting_error_matrix": "constrained_fit", "project_to_so4": "constrained_fit",
    "random_layout_rad": "constrained_fit", "simulate_calibration_errors": "constrained_fit",
    "so4_error_matrix": "constrained_fit", "so4_from_quaternions": "constrained_fit",
    "symmetric_layout_rad": "constrained_fit", "MAX_RATE_RAD_S": "gyro_roll", "body_rates_two_dof": "gyro_roll",
    "euler_differential": "gyro_roll", "loglog_slope": "gyro_roll", "pitch_rate_magnitude": "gyro_roll",
    "projection_roll_error_eq14": "gyro_roll", "projection_roll_error_exact": "gyro_roll",
    "roll_decoupled_integration": "gyro_roll", "roll_hybrid": "gyro_roll", "roll_hybrid_rmse_sweep": "gyro_roll",
    "roll_projection": "gyro_roll", "simulate_two_dof_imu": "gyro_roll", "two_dof_trajectory": "gyro_roll",
    "LAMBDA1_RAD": "large_angle", "LAMBDA2_RAD": "large_angle", "bias_moment_matrix": "large_angle",
    "monte_carlo_pitch_errors": "large_angle", "perturbed_errors": "large_angle",
    "perturbed_preset_pitch_error": "large_angle", "pitch_error_eq10": "large_angle",
    "pitch_error_eq3_printed": "large_angle", "pitch_error_eq8": "large_angle",
    "pitch_error_first_order": "large_angle", "pitch_roll_eq2": "large_angle",
    "pitch_roll_from_preset_triad": "large_angle", "preset_lambda": "large_angle", "preset_matrix": "large_angle",
    "preset_specific_force": "large_angle", "rms_pitch_error_from_moments": "large_angle",
    "roll_error_eq4": "large_angle", "select_preset_pitch": "large_angle", "align_pairs": "quaternion_lsq",
    "apply_error_matrix": "quaternion_lsq", "least_squares_error_matrix": "quaternion_lsq",
    "RejectedRest": "rest_detection", "RestDetectorParams": "rest_detection", "RestReport": "rest_detection",
    "detect_rests": "rest_detection", "paper_rest_report": "rest_detection", "AxisEstimator": "rotation_axis",
    "AxisPlaneFit": "rotation_axis", "AxisResult": "rotation_axis", "angle_between": "rotation_axis",
    "apply_sign_convention": "rotation_axis", "axis_elevation": "rotation_axis", "axis_error_std": "rotation_axis",
    "axis_from_means": "rotation_axis", "distinct_positions": "rotation_axis", "estimate_axis": "rotation_axis",
    "fit_axis_plane": "rotation_axis", "gravity_change_norm": "rotation_axis", "rest_attitudes": "six_position",
    "find_rests": "six_position", "match_rests": "six_position",
    "mean_quaternion": "six_position", "middle_slices": "six_position", "rest_means": "six_position",
    "schedule_profile": "six_position", "six_positions_rad": "six_position", "stillness_from_gyro": "six_position",
    "stillness_from_quaternions": "six_position", "ZvdParams": "zero_velocity", "detect_static": "zero_velocity",
    "moving_variance": "zero_velocity", "rest_intervals": "zero_velocity",
}

__getattr__, __dir__ = lazy_attributes(globals(), _SUBMODULES, _EXPORTS)
