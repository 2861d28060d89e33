"""Study of broad2021 — the BROAD benchmark: real IMU trials with optical ground truth.

Laidig D., Caruso M., Cereatti A., Seel T., "BROAD — A Benchmark for Robust Inertial Orientation
Estimation", Data 2021, 6(7):72, doi:10.3390/data6070072; data (CC BY 4.0) in the repository's
``datasets/broad2021`` (14 of 39 trials, BROAD's published case-study results).

Modules by role (``docs/study_template.md``): :mod:`.scenario` (where the data live, the
:class:`~.scenario.Trial` loader, the settings), :mod:`.runs` (6D filters and BROAD's 9D
Madgwick/Mahony on the real trials, BROAD's error metric), :mod:`.error_model` (the simulated twin
of a trial, built blind, and :func:`~.error_model.predict_real_error`), :mod:`.artifacts` (one
producer per table/figure of notebook 60), :mod:`.plots` (figures, on demand).
"""

import numpy as np

from mtcal.reporting import leak

from . import scenario, runs, error_model, artifacts
from .scenario import (DATA_ENV, data_dir, Trial, load_trial, trial_from_arrays, trial_names, load_trials,
                       trial_groups, trial_head, GROUP_CATEGORIES, FILTERS_6D, BroadScenario, PARAMETER_DEFAULTS,
                       scenario_from_parameters, broad_parameters)
from .runs import run_6d, errors_deg, rmse_deg, run_9d, initial_rest
from .error_model import (STREAM_TWIN, RestModel, identify_rest_model, twin_truth, simulate_twin, TwinPrediction,
                          twin_predictions, predict_real_error)
from .artifacts import (StudyRun, run_study, table_published_vs_ours, extra_bakeoff_6d, extra_median_trial,
                        extra_rankings, extra_twin, TOLERANCE_DEG)

__all__ = ["scenario", "runs", "error_model", "artifacts", "plots", "DATA_ENV", "data_dir", "Trial", "load_trial",
           "trial_from_arrays", "trial_names", "load_trials", "trial_groups", "trial_head", "GROUP_CATEGORIES", "FILTERS_6D",
           "BroadScenario", "PARAMETER_DEFAULTS", "scenario_from_parameters", "broad_parameters", "run_6d",
           "errors_deg", "rmse_deg", "run_9d", "initial_rest", "STREAM_TWIN", "RestModel",
           "identify_rest_model", "twin_truth", "simulate_twin", "TwinPrediction", "twin_predictions",
           "predict_real_error", "StudyRun", "run_study", "table_published_vs_ours", "extra_bakeoff_6d",
           "extra_median_trial", "extra_rankings", "extra_twin", "TOLERANCE_DEG"]


def __getattr__(name):
    if name == "plots":  # matplotlib only when a figure is asked for
        import importlib

        return importlib.import_module(f"{__name__}.plots")
    raise AttributeError(name)


@leak.register("broad2021")
def fit_and_predict(size: str = "ci", seed: int = 0) -> dict:
    """What notebook 60 computes before comparing (never reads the held-out published numbers):
    the 9D RMSE at BROAD's parameters and the twin's draws, on the first trial (CI: its first 56 s)."""
    sc = scenario_from_parameters(trials=[trial_names()[0]], filters=["mahony"], n_draws=2,
                                  max_samples=None if size == "full" else 16000)
    tr = trial_head(load_trials(sc.trials)[0], sc.max_samples)
    res = run_9d(tr, [sc.madgwick_beta], [sc.mahony_kp], [sc.mahony_ki])
    twin = predict_real_error(tr, "mahony", n_draws=2, seed=seed)
    return {"madgwick": np.asarray(res["madgwick"]), "mahony": np.asarray(res["mahony"]), "twin": twin.rmse_deg}
