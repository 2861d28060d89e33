"""Study of wang2023cja — installation-error calibration of a MEMS angular measurement system.

Wang X., Zhao X., Zhou B., Wei Q., Zhang R., "Installation error calibration for MEMS
angular measurement system in hypersonic wind tunnel", Chin. J. Aeronaut. 2023,
doi:10.1016/j.cja.2022.12.006. QNCF filter, least-squares error quaternion (Eq 10–14),
six-position procedure, turntable Tables 1–8, wind tunnel Tables 9–11.

Modules by role (``docs/study_template.md``): :mod:`.scenario` (frozen scenario dataclasses,
the IMU as a :class:`mtcal.core.sensors.SensorSpec`, parameter defaults, builders),
:mod:`.error_model` (the hardware error model's priors, identified from Tables 1–4 and the
printed matrices), :mod:`.runs` (simulation runs), :mod:`.artifacts` (one producer per
table/figure, plus comparison rows), :mod:`.plots` (figures; imports matplotlib on call);
:mod:`.constrained` (the constrained-calibration question of notebook 40); :mod:`.predictive`
(predictive bands: one parameter draw per trial, fitted posterior or prior) and :mod:`.verdicts`
(every printed number one to one, scores, the paper's claims with its thresholds); :mod:`.crossval`
(leave-one-table-out cross-validation over Tables 1–4 against two baselines).
"""

from . import artifacts, constrained, crossval, error_model, predictive, runs, scenario, verdicts
from .artifacts import (banded, error_budget_table, error_metric_table, error_model_table, HELD_OUT,
                        installation_fit_table, outside_rows, positions_table, printed_matrix_check, q22_noise_band,
                        stepwise_coupling, sweep_mean_table, table08_reductions, TRAINING, TUNED,
                        windtunnel_matrix_table, wind_on_table, PRODUCERS, extra_installation_fit, extra_q33_roll,
                        extra_error_model, table01, table02, table03, table04, table05, table06, table07, table08,
                        extra_error_budget, extra_windtunnel_matrix, table09, table10, table11, extra_min_positions,
                        extra_error_vs_positions, extra_error_vs_noise, extra_constrained_headline,
                        extra_printed_matrices_so4, extra_q33_sign, extra_noise_vs_so4_distance)
from .error_model import (ErrorModel, ErrorModelFit, fit_error_model, fit_installation_angles, FITTED_PARAMETERS,
                          InstallationFit, MOUNT_TYPE, N_NORMALS, paper_positions, PAPER_SIGN, position_noise_deg,
                          predicted_before, PRIOR_RANGES, rest_residuals, rest_times_s, TABLES_1_TO_4,
                          true_error_matrix)
from .runs import (calibration_step, MONTE_CARLO_GATES, elastic_deflection_rad, load_tilt_outputs, position_errors_deg,
                   run_turntable, run_turntable_jobs, run_windtunnel, six_position_reference, turntable_profile,
                   turntable_runs, TurntableJob, TurntableRun, WindTunnelRun)
from .scenario import (compliance_trajectory, identify_pitch_ratio, IMU_ASSUMPTIONS, ImuSpec, mechanism_actual, paper_imu,
                       windtunnel_positions, PRINTED_WINDTUNNEL_Q22, SOURCES, TURNTABLE_DEFAULTS, turntable_scenario,
                       TurntableScenario, WINDTUNNEL_DEFAULTS, windtunnel_geometry, windtunnel_scenario,
                       WindTunnelScenario)

__all__ = ["artifacts", "constrained", "crossval", "error_model", "predictive", "runs", "scenario", "verdicts", "plots", "PAPER_SIGN", "TABLES_1_TO_4",
           "MOUNT_TYPE", "PRIOR_RANGES", "FITTED_PARAMETERS", "ErrorModel", "InstallationFit",
           "fit_installation_angles", "true_error_matrix", "predicted_before", "paper_positions", "rest_times_s",
           "rest_residuals", "N_NORMALS", "ErrorModelFit", "fit_error_model", "position_noise_deg", "SOURCES",
           "ImuSpec", "IMU_ASSUMPTIONS", "paper_imu", "TurntableScenario", "WindTunnelScenario", "TURNTABLE_DEFAULTS", "WINDTUNNEL_DEFAULTS",
           "turntable_scenario", "windtunnel_scenario", "windtunnel_geometry", "PRINTED_WINDTUNNEL_Q22",
           "turntable_runs", "windtunnel_positions", "identify_pitch_ratio", "turntable_profile",
           "six_position_reference", "TurntableRun", "TurntableJob", "run_turntable", "run_turntable_jobs",
           "position_errors_deg", "compliance_trajectory", "load_tilt_outputs", "mechanism_actual", "WindTunnelRun",
           "run_windtunnel", "elastic_deflection_rad", "calibration_step", "MONTE_CARLO_GATES", "TRAINING", "TUNED", "HELD_OUT", "installation_fit_table",
           "error_model_table", "printed_matrix_check", "positions_table", "sweep_mean_table", "error_metric_table",
           "table08_reductions", "windtunnel_matrix_table", "wind_on_table", "banded",
           "outside_rows", "q22_noise_band", "stepwise_coupling", "error_budget_table",
           # one producer per artifact (artifacts.PRODUCERS)
           "PRODUCERS", "extra_installation_fit", "extra_q33_roll", "extra_error_model", "table01", "table02",
           "table03", "table04", "table05", "table06", "table07", "table08", "extra_error_budget",
           "extra_windtunnel_matrix", "table09", "table10", "table11", "extra_min_positions",
           "extra_error_vs_positions", "extra_error_vs_noise", "extra_constrained_headline",
           "extra_printed_matrices_so4", "extra_q33_sign", "extra_noise_vs_so4_distance"]


def __getattr__(name):
    if name == "plots":  # matplotlib only when a figure is asked for
        import importlib

        return importlib.import_module(f"{__name__}.plots")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
