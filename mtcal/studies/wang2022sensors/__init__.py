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
from .scenario import *  # noqa: F401,F403
from .runs import *  # noqa: F401,F403
from .error_model import *  # noqa: F401,F403
from .artifacts import *  # noqa: F401,F403

__all__ = ["scenario", "runs", "error_model", "artifacts", "plots"]
__all__ += [n for m in (scenario, runs, error_model, artifacts) for n in m.__all__ if n not in __all__]
