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
from .artifacts import *  # noqa: F401,F403
from .error_model import *  # noqa: F401,F403
from .runs import *  # noqa: F401,F403
from .scenario import *  # noqa: F401,F403

__all__ = ["scenario", "error_model", "runs", "artifacts", "plots"]
__all__ += [n for m in (scenario, error_model, runs, artifacts) for n in m.__all__ if n not in __all__]


def __getattr__(name):
    if name == "plots":  # matplotlib only on demand
        import importlib

        return importlib.import_module(f"{__name__}.plots")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
