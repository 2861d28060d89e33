"""Study of tan2022 — large-angle pitch/roll measurement with pitch/roll coupling.

Tan Q., Cheng Y., Tang B., Liu X., Zhou H., Li Y., "Large-angle attitude measurement
algorithm with pitch/roll coupling" (in Chinese), J. Terahertz Sci. Electron. Inf.
Technol. 2022, 20(9):946–952, doi:10.11805/TKYDA2020404. Accelerometer error
contours (Fig 2, 5, 8), preset Euler rotation, gyro roll decoupling (Fig 6, 9–12).

Modules by role (``docs/study_template.md``): :mod:`.scenario` (frozen dataclasses,
parameter defaults, builders), :mod:`.error_model` (the priors and the fits),
:mod:`.runs` (Monte Carlo over the procedures), :mod:`.artifacts` (one producer per
figure/table, returning a :class:`mtcal.core.artifacts.Artifact`), :mod:`.plots`
(figures; the only module importing matplotlib).
"""

from . import artifacts, error_model, runs, scenario
from .artifacts import (Artifact, accel_label, eq3_erratum, fig02, extra_roll_error, fig05, fig08,
                        extra_independent_errors, gyro_label, fig06, threshold_check, fig09, fig10, fig11, fig12,
                        extra_threshold_sweep)
from .error_model import (AccelErrorPrior, GyroErrorPrior, ErrorModelFit, grid_posterior, fit_accel_error_model,
                          fit_gyro_error_model, fit_gyro_error_pattern, paper_gyro_error_deg_s,
                          PATTERN_BIAS_GRID_DEG_S, PATTERN_NOISE_GRID_DEG_S_RTHZ, IMPLIED_MIN, implied_by_training)
from .runs import (STREAM_FIG06, STREAM_FIG09, STREAM_OSCILLATION, STREAM_INDEPENDENT_ERRORS, STREAM_ACCEL_FIT,
                   STREAM_GYRO_FIT, STREAM_GYRO_PATTERN, simulate_gyro, oscillation_gyro, accel_grid, fig02_asymmetry,
                   axis_spread, large_pitch_ratio, accel_predictions, gyro_samples, trial_chunks, gyro_predictions,
                   oscillation_claims)
from .scenario import (AccelScenario, GyroErrors, ProjectionSweep, UniformRotation, Oscillation, GyroStudy,
                       ACCEL_PARAMETER_DEFAULTS, GYRO_PARAMETER_DEFAULTS, PARAMETER_DEFAULTS, accel_scenario,
                       gyro_study)

__all__ = ["scenario", "error_model", "runs", "artifacts", "plots",
           "Artifact", "accel_label", "eq3_erratum", "fig02", "extra_roll_error", "fig05", "fig08",
           "extra_independent_errors", "gyro_label", "fig06", "threshold_check", "fig09", "fig10", "fig11",
           "fig12", "extra_threshold_sweep", "AccelErrorPrior", "GyroErrorPrior", "ErrorModelFit",
           "grid_posterior", "fit_accel_error_model", "fit_gyro_error_model", "fit_gyro_error_pattern",
           "paper_gyro_error_deg_s", "PATTERN_BIAS_GRID_DEG_S", "PATTERN_NOISE_GRID_DEG_S_RTHZ",
           "IMPLIED_MIN", "implied_by_training", "STREAM_FIG06", "STREAM_FIG09", "STREAM_OSCILLATION", "STREAM_INDEPENDENT_ERRORS",
           "STREAM_ACCEL_FIT", "STREAM_GYRO_FIT", "STREAM_GYRO_PATTERN", "simulate_gyro",
           "oscillation_gyro", "accel_grid", "fig02_asymmetry", "axis_spread", "large_pitch_ratio",
           "accel_predictions", "gyro_samples", "trial_chunks", "gyro_predictions", "oscillation_claims",
           "AccelScenario", "GyroErrors", "ProjectionSweep", "UniformRotation", "Oscillation", "GyroStudy",
           "ACCEL_PARAMETER_DEFAULTS", "GYRO_PARAMETER_DEFAULTS", "PARAMETER_DEFAULTS", "accel_scenario",
           "gyro_study"]


def __getattr__(name):
    if name == "plots":  # matplotlib only when a figure is asked for
        import importlib

        return importlib.import_module(f"{__name__}.plots")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
