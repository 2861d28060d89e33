"""Paper-independent core: conventions, simulation, motion profiles, metrics, Monte Carlo, validation.

Nothing here names a paper. Radians and SI units throughout.

The public names of every submodule are re-exported here (see ``__all__``).
"""

from . import rotations, simulate, profiles, metrics, montecarlo, validate, units, sensor_grades
from .rotations import *  # noqa: F401,F403
from .simulate import *  # noqa: F401,F403
from .profiles import *  # noqa: F401,F403
from .metrics import *  # noqa: F401,F403
from .montecarlo import *  # noqa: F401,F403
from .validate import *  # noqa: F401,F403
from .units import *  # noqa: F401,F403
from .sensor_grades import *  # noqa: F401,F403
import sys as _sys  # noqa: E402

# the submodules, not same-named functions (e.g. filters.qncf the module, filters.qncf.qncf the function)
rotations, simulate, profiles, metrics, montecarlo, validate, units, sensor_grades = (_sys.modules[f"{__name__}.{_n}"] for _n in ('rotations', 'simulate', 'profiles', 'metrics', 'montecarlo', 'validate', 'units', 'sensor_grades'))

__all__ = ["rotations", "simulate", "profiles", "metrics", "montecarlo", "validate", "units", "sensor_grades"]
__all__ += [n for m in (rotations, simulate, profiles, metrics, montecarlo, validate, units, sensor_grades) for n in m.__all__ if n not in __all__]
