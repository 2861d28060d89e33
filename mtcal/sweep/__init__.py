"""Parameter sweeps: a grid of scenario parameters × Monte Carlo trials on local cores or a Dask cluster.

``run_sweep(spec)`` gives the same tidy table (median, 2.5 and 97.5 percentiles per cell and
metric) for any number of workers, any executor and any interruption/resume.
See :mod:`mtcal.sweep.spec` (TOML format), :mod:`mtcal.sweep.evaluators` (what a
cell computes), :mod:`mtcal.sweep.engine` (determinism, run folder) and
:mod:`mtcal.sweep.executors` (local processes, Dask).
"""

from . import bakeoff, engine, evaluators, executors, spec
from .bakeoff import (BAKEOFF_DEFAULTS, bakeoff_figure, bakeoff_params, BakeoffResult, FAMILIES, family_specs,
                      findings, headline_table, run_bakeoff, tune_gains)
from .engine import run_block, run_sweep, summarize, SweepResult, TABLE_COLUMNS, trial_rngs
from .evaluators import (attitude_profile, Evaluator, evaluator_names, filter_gain, get_evaluator, MOTIONS,
                         RAMS_EKF_DEFAULT_GAIN, register_evaluator, SURFACE_AXIS, surface_profile,
                         validation_positions_rad)
from .executors import DaskExecutor, LocalExecutor, make_executor, SerialExecutor
from .spec import load_spec, parse_spec, SweepSpec

__all__ = ["bakeoff", "engine", "evaluators", "executors", "spec", "BAKEOFF_DEFAULTS", "FAMILIES", "bakeoff_params",
           "family_specs", "tune_gains", "BakeoffResult", "run_bakeoff", "headline_table", "bakeoff_figure",
           "findings", "SweepResult", "run_sweep", "run_block", "trial_rngs", "summarize", "TABLE_COLUMNS",
           "Evaluator", "register_evaluator", "get_evaluator", "evaluator_names", "MOTIONS", "filter_gain",
           "RAMS_EKF_DEFAULT_GAIN", "SURFACE_AXIS", "attitude_profile", "surface_profile", "validation_positions_rad",
           "SerialExecutor", "LocalExecutor", "DaskExecutor", "make_executor", "SweepSpec", "parse_spec", "load_spec"]
