"""Study of wang2022sensors — movable-surface rotation angle measurement (RAMS).

Wang C., Tu X., Chen Q., Yang Q., Fang T., "Movable Surface Rotation Angle Measurement
System Using IMU", Sensors 2022, 22, 8996, doi:10.3390/s22228996. Rotation axis from
three rests, zero-velocity detection, EKF (Tables 1–5, Fig 6, 9, 11–14).

Modules by role (``docs/study_template.md``): :mod:`.scenario` (frozen dataclasses,
the Table 3 IMU as a :class:`mtcal.core.sensors.SensorSpec`, parameters-cell defaults),
:mod:`.runs` (simulation and Monte Carlo pipelines on resolved values),
:mod:`.error_model` (the priors, identification from Table 5 and held-out predictions),
:mod:`.artifacts` (one producer per table/figure, returning a
:class:`mtcal.core.artifacts.Artifact`), :mod:`.plots` (figures).
"""

from . import scenario, runs, error_model, artifacts, plots
from .scenario import (PAPER_AXIS_FIG11, table4_axes, ImuSpec, ImuValues, table3_imu, table3_reading, imu_from_grade,
                       rams_ekf_params, AhrsImu, RigSetup, RigValues, Scenario, PARAMETER_DEFAULTS,
                       scenario_from_parameters, labels, lever_arm_vector, gravity0, table1_zvd_params)
from .runs import (trapezoid_profile, sweep_profile, simulate_batch, SimBatch, SweepMetrics, sweep_metrics,
                   ahrs_sweep_metrics, Fig11Result, run_fig11, DriftResult, run_drift, axis_errors, Fig9Result,
                   run_fig9, ZvdDemo, run_zvd_demo, RotationSetup, RotationRecord, simulate_rotation)
from .error_model import (ERROR_PRIORS, FIT_GRID, FIT_GRID_CI, LATENCY_GRID_S, TRAINING, HELD_OUT, DISCREPANCY_LOG_SD,
                          SYSTEMS, GridRun, run_grid, paper_table5, log_likelihood, posterior_weights, prior_weights,
                          parameter_summary, predictive_samples, weighted_quantile, fig14_samples, ErrorModelFit,
                          fit_error_model, error_model_priors_table)
from .artifacts import (Artifact, table01_zvd, fig06_zvd, table02_sensors, fig12_gravity_change, table04_axes,
                        extra_axis_error_vs_rest, fig09_ekf_switching, fig11_max_error, extra_table3_sensitivity,
                        extra_error_model, outside_reasons, table05_rmse, fig13_drift, fig14_max_error_per_angle)

__all__ = ["scenario", "runs", "error_model", "artifacts", "plots",
           "PAPER_AXIS_FIG11", "table4_axes", "ImuSpec", "ImuValues", "table3_imu", "table3_reading",
           "imu_from_grade", "rams_ekf_params", "AhrsImu", "RigSetup", "RigValues", "Scenario",
           "PARAMETER_DEFAULTS", "scenario_from_parameters", "labels", "lever_arm_vector", "gravity0",
           "table1_zvd_params", "trapezoid_profile", "sweep_profile", "simulate_batch", "SimBatch",
           "SweepMetrics", "sweep_metrics", "ahrs_sweep_metrics", "Fig11Result", "run_fig11",
           "DriftResult", "run_drift", "axis_errors", "Fig9Result", "run_fig9", "ZvdDemo", "run_zvd_demo",
           "RotationSetup", "RotationRecord", "simulate_rotation", "ERROR_PRIORS", "FIT_GRID",
           "FIT_GRID_CI", "LATENCY_GRID_S", "TRAINING", "HELD_OUT", "DISCREPANCY_LOG_SD", "SYSTEMS",
           "GridRun", "run_grid", "paper_table5", "log_likelihood", "posterior_weights", "prior_weights",
           "parameter_summary", "predictive_samples", "weighted_quantile", "fig14_samples",
           "ErrorModelFit", "fit_error_model", "error_model_priors_table", "Artifact", "table01_zvd",
           "fig06_zvd", "table02_sensors", "fig12_gravity_change", "table04_axes",
           "extra_axis_error_vs_rest", "fig09_ekf_switching", "fig11_max_error",
           "extra_table3_sensitivity", "extra_error_model", "outside_reasons", "table05_rmse",
           "fig13_drift", "fig14_max_error_per_angle"]
