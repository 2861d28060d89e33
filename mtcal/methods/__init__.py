"""Methods, named by what they compute (each cites the paper equation it implements).

* :mod:`~mtcal.methods.quaternion_lsq` — least-squares error quaternion matrix (Wang2023 Eq 10–14)
* :mod:`~mtcal.methods.constrained_fit` — SO(4) and 3-DOF mounting fits (beyond the papers)
* :mod:`~mtcal.methods.six_position` — six-position calibration procedure (Wang2023 §3.2)
* :mod:`~mtcal.methods.large_angle` — large-angle accelerometer pitch/roll, preset rotation (Tan2022 Eq 2–10)
* :mod:`~mtcal.methods.gyro_roll` — gyro roll decoupling, projection, hybrid (Tan2022 Eq 5, 12–14)
* :mod:`~mtcal.methods.rotation_axis` — rotation axis from three rests (Wang2022 Algorithm A1)
* :mod:`~mtcal.methods.zero_velocity` — zero-velocity (rest) detection (Wang2022 Table 1)
* :mod:`~mtcal.methods.rest_detection` — rest detection with levels measured from the data (any sensor)

The public names of every submodule are re-exported here (see ``__all__``).
"""

from . import quaternion_lsq, constrained_fit, six_position, large_angle, gyro_roll, rotation_axis, zero_velocity, rest_detection
from .quaternion_lsq import *  # noqa: F401,F403
from .constrained_fit import *  # noqa: F401,F403
from .six_position import *  # noqa: F401,F403
from .large_angle import *  # noqa: F401,F403
from .gyro_roll import *  # noqa: F401,F403
from .rotation_axis import *  # noqa: F401,F403
from .zero_velocity import *  # noqa: F401,F403
from .rest_detection import *  # noqa: F401,F403
import sys as _sys  # noqa: E402

# the submodules, not same-named functions (e.g. filters.qncf the module, filters.qncf.qncf the function)
quaternion_lsq, constrained_fit, six_position, large_angle, gyro_roll, rotation_axis, zero_velocity, rest_detection = (_sys.modules[f"{__name__}.{_n}"] for _n in ('quaternion_lsq', 'constrained_fit', 'six_position', 'large_angle', 'gyro_roll', 'rotation_axis', 'zero_velocity', 'rest_detection'))

__all__ = ["quaternion_lsq", "constrained_fit", "six_position", "large_angle", "gyro_roll", "rotation_axis", "zero_velocity", "rest_detection"]
__all__ += [n for m in (quaternion_lsq, constrained_fit, six_position, large_angle, gyro_roll, rotation_axis, zero_velocity, rest_detection) for n in m.__all__ if n not in __all__]
