"""Study of wang2022sensors — movable-surface rotation angle measurement (RAMS).

Wang C., Tu X., Chen Q., Yang Q., Fang T., "Movable Surface Rotation Angle Measurement
System Using IMU", Sensors 2022, 22, 8996, doi:10.3390/s22228996. Rotation axis from
three rests, zero-velocity detection, EKF (Tables 1–5, Fig 6, 9, 11–14).
"""

from . import runs
from .runs import *  # noqa: F401,F403
import sys as _sys  # noqa: E402

# the submodules, not same-named functions (e.g. filters.qncf the module, filters.qncf.qncf the function)
runs = (_sys.modules[f"{__name__}.{_n}"] for _n in ('runs',))

__all__ = ["runs"]
__all__ += [n for m in (runs) for n in m.__all__ if n not in __all__]
