"""Study of wang2023cja — installation-error calibration of a MEMS angular measurement system.

Wang X., Zhao X., Zhou B., Wei Q., Zhang R., "Installation error calibration for MEMS
angular measurement system in hypersonic wind tunnel", Chin. J. Aeronaut. 2023,
doi:10.1016/j.cja.2022.12.006. QNCF filter, least-squares error quaternion (Eq 10–14),
six-position procedure, turntable Tables 1–8, wind tunnel Tables 9–11.
"""

from . import runs
from .runs import *  # noqa: F401,F403
import sys as _sys  # noqa: E402

# the submodules, not same-named functions (e.g. filters.qncf the module, filters.qncf.qncf the function)
runs = (_sys.modules[f"{__name__}.{_n}"] for _n in ('runs',))

__all__ = ["runs"]
__all__ += [n for m in (runs) for n in m.__all__ if n not in __all__]
