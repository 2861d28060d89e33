"""Study of wang2022sensors — movable-surface rotation angle measurement (RAMS).

Wang C., Tu X., Chen Q., Yang Q., Fang T., "Movable Surface Rotation Angle Measurement
System Using IMU", Sensors 2022, 22, 8996, doi:10.3390/s22228996. Rotation axis from
three rests, zero-velocity detection, EKF (Tables 1–5, Fig 6, 9, 11–14).

Modules by role: :mod:`.scenario` (frozen dataclasses, priors, parameters-cell
defaults), :mod:`.runs` (simulation and Monte Carlo pipelines on resolved values),
:mod:`.error_model` (identification from Table 5 and held-out predictions),
:mod:`.artifacts` (one producer per table/figure), :mod:`.plots` (figures).
"""

from . import artifacts, error_model, plots, runs, scenario
from .scenario import (AhrsImu, ERROR_PRIORS, gravity0, ImuValues, labels, lever_arm_vector, PAPER_AXIS_FIG11,
                       PARAMETER_DEFAULTS, RigSetup, RigValues, Scenario, scenario_from_parameters, table1_zvd_params,
                       table4_axes)
from .runs import (ahrs_sweep_metrics, axis_errors, DriftResult, Fig11Result, Fig9Result, ImuSpec, RotationRecord,
                   RotationSetup, run_drift, run_fig11, run_fig9, run_zvd_demo, SimBatch, simulate_batch,
                   simulate_rotation, sweep_metrics, sweep_profile, SweepMetrics, trapezoid_profile, ZvdDemo)
from .artifacts import (Artifact, error_model_priors_table, ErrorModelFit, extra_axis_error_vs_rest,
                        extra_error_model, extra_table3_sensitivity, fig06_zvd, fig09_ekf_switching, fig11_max_error,
                        fig12_gravity_change, fig13_drift, fig14_max_error_per_angle, fit_error_model,
                        outside_reasons, table01_zvd, table02_sensors, table04_axes, table05_rmse)

__all__ = ["scenario", "runs", "error_model", "artifacts", "plots", "PAPER_AXIS_FIG11", "table4_axes", "ImuSpec",
           "ImuValues", "AhrsImu", "RigSetup", "RigValues", "ERROR_PRIORS", "Scenario", "PARAMETER_DEFAULTS",
           "scenario_from_parameters", "labels", "lever_arm_vector", "gravity0", "trapezoid_profile", "sweep_profile",
           "simulate_batch", "SimBatch", "SweepMetrics", "sweep_metrics", "ahrs_sweep_metrics", "Fig11Result",
           "run_fig11", "DriftResult", "run_drift", "axis_errors", "Fig9Result", "run_fig9", "ZvdDemo",
           "run_zvd_demo", "RotationSetup", "RotationRecord", "simulate_rotation", "Artifact", "table01_zvd",
           "fig06_zvd", "table02_sensors", "fig12_gravity_change", "table04_axes", "extra_axis_error_vs_rest",
           "fig09_ekf_switching", "fig11_max_error", "ErrorModelFit", "extra_table3_sensitivity", "fit_error_model",
           "error_model_priors_table", "extra_error_model", "outside_reasons", "table05_rmse", "fig13_drift",
           "fig14_max_error_per_angle", "table1_zvd_params"]
