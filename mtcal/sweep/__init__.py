"""Parameter sweeps: a grid of scenario parameters × Monte Carlo trials on local cores or a Dask cluster.

``run_sweep(spec)`` gives the same tidy table (median and 95 % band per cell and
metric) for any number of workers, any executor and any interruption/resume.
See :mod:`mtcal.sweep.spec` (TOML format), :mod:`mtcal.sweep.evaluators` (what a
cell computes), :mod:`mtcal.sweep.engine` (determinism, run folder) and
:mod:`mtcal.sweep.executors` (local processes, Dask).
"""

from . import bakeoff, engine, evaluators, executors, spec
from .bakeoff import *  # noqa: F401,F403
from .engine import *  # noqa: F401,F403
from .evaluators import *  # noqa: F401,F403
from .executors import *  # noqa: F401,F403
from .spec import *  # noqa: F401,F403

__all__ = ["bakeoff", "engine", "evaluators", "executors", "spec"]
__all__ += [n for m in (bakeoff, engine, evaluators, executors, spec) for n in m.__all__ if n not in __all__]
