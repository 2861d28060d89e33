"""Attitude filters: QNCF (Wang2023), the RAMS EKF (Wang2022), baselines, an IMU-only Mahony,
and adapters to the anchor libraries (vqf, imufusion, ahrs) for the bake-off.

The public names of every submodule are re-exported here (see ``__all__``).
"""

from . import qncf, rams_ekf, baselines, mahony, anchors
from .qncf import *  # noqa: F401,F403
from .rams_ekf import *  # noqa: F401,F403
from .baselines import *  # noqa: F401,F403
from .mahony import *  # noqa: F401,F403
from .anchors import *  # noqa: F401,F403
import sys as _sys  # noqa: E402

# the submodules, not same-named functions (e.g. filters.qncf the module, filters.qncf.qncf the function)
qncf, rams_ekf, baselines, mahony, anchors = (_sys.modules[f"{__name__}.{_n}"] for _n in
                                             ('qncf', 'rams_ekf', 'baselines', 'mahony', 'anchors'))

__all__ = ["qncf", "rams_ekf", "baselines", "mahony", "anchors"]
__all__ += [n for m in (qncf, rams_ekf, baselines, mahony, anchors) for n in m.__all__ if n not in __all__]
