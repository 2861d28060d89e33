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
from .artifacts import *  # noqa: F401,F403
from .error_model import *  # noqa: F401,F403
from .scenario import *  # noqa: F401,F403

__all__ = ["scenario", "artifacts", "error_model", "plots"]
__all__ += [n for m in (scenario, artifacts, error_model) for n in m.__all__ if n not in __all__]


def __getattr__(name):
    if name == "plots":  # matplotlib only on demand
        import importlib

        return importlib.import_module(f"{__name__}.plots")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
