"""Study of tan2022 — large-angle pitch/roll measurement with pitch/roll coupling.

Tan Q., Cheng Y., Tang B., Liu X., Zhou H., Li Y., "Large-angle attitude measurement
algorithm with pitch/roll coupling" (in Chinese), J. Terahertz Sci. Electron. Inf.
Technol. 2022, 20(9):946–952, doi:10.11805/TKYDA2020404. Accelerometer error
contours (Fig 2, 5, 8), preset Euler rotation, gyro roll decoupling (Fig 6, 9–12).

Modules: :mod:`.scenario` (frozen dataclasses, parameter defaults, builders),
:mod:`.artifacts` (one producer per figure/table, returning its data and
comparison rows), :mod:`.error_model` (the identified error models and their
fits), :mod:`.plots` (figures; the only module importing matplotlib).
"""

from . import artifacts, error_model, scenario
from .artifacts import (accel_label, Artifact, artifact_rng, eq3_erratum, extra_independent_errors, extra_roll_error,
                        extra_threshold_sweep, fig02, fig05, fig06, fig08, fig09, fig10, fig11, fig12, gyro_label,
                        threshold_check)
from .error_model import (ErrorModelFit, fit_accel_error_model, fit_gyro_error_model, fit_gyro_error_pattern,
                          grid_posterior, paper_gyro_error_deg_s, PATTERN_BIAS_GRID_DEG_S,
                          PATTERN_NOISE_GRID_DEG_S_RTHZ)
from .scenario import (ACCEL_PARAMETER_DEFAULTS, accel_scenario, AccelErrorPrior, AccelScenario,
                       GYRO_PARAMETER_DEFAULTS, gyro_study, GyroErrorPrior, GyroErrors, GyroStudy, Oscillation,
                       PARAMETER_DEFAULTS, ProjectionSweep, UniformRotation)

__all__ = ["scenario", "artifacts", "error_model", "plots", "AccelScenario", "GyroErrors", "ProjectionSweep",
           "UniformRotation", "Oscillation", "GyroStudy", "AccelErrorPrior", "GyroErrorPrior",
           "ACCEL_PARAMETER_DEFAULTS", "GYRO_PARAMETER_DEFAULTS", "PARAMETER_DEFAULTS", "accel_scenario",
           "gyro_study", "Artifact", "accel_label", "eq3_erratum", "fig02", "extra_roll_error", "fig05", "fig08",
           "extra_independent_errors", "gyro_label", "fig06", "threshold_check", "fig09", "fig10", "fig11", "fig12",
           "extra_threshold_sweep", "artifact_rng", "ErrorModelFit", "grid_posterior", "fit_accel_error_model",
           "fit_gyro_error_model", "fit_gyro_error_pattern", "paper_gyro_error_deg_s", "PATTERN_BIAS_GRID_DEG_S",
           "PATTERN_NOISE_GRID_DEG_S_RTHZ"]


def __getattr__(name):
    if name == "plots":  # matplotlib only when a figure is asked for
        import importlib

        return importlib.import_module(f"{__name__}.plots")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
