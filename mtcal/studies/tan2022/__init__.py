"""Study of tan2022 — large-angle pitch/roll measurement with pitch/roll coupling.

Tan Q., Cheng Y., Tang B., Liu X., Zhou H., Li Y., "Large-angle attitude measurement
algorithm with pitch/roll coupling" (in Chinese), J. Terahertz Sci. Electron. Inf.
Technol. 2022, 20(9):946–952. Accelerometer error contours (Fig 2, 5, 8), preset Euler
rotation, gyro roll decoupling (Fig 6, 9–12).
"""

from . import scenario
from .scenario import *  # noqa: F401,F403
import sys as _sys  # noqa: E402

# the submodules, not same-named functions (e.g. filters.qncf the module, filters.qncf.qncf the function)
scenario = (_sys.modules[f"{__name__}.{_n}"] for _n in ('scenario',))

__all__ = ["scenario"]
__all__ += [n for m in (scenario) for n in m.__all__ if n not in __all__]
