"""Study of wang2023cja — installation-error calibration of a MEMS angular measurement system.

Wang X., Zhao X., Zhou B., Wei Q., Zhang R., "Installation error calibration for MEMS
angular measurement system in hypersonic wind tunnel", Chin. J. Aeronaut. 2023,
doi:10.1016/j.cja.2022.12.006. QNCF filter, least-squares error quaternion (Eq 10–14),
six-position procedure, turntable Tables 1–8, wind tunnel Tables 9–11.

Modules by role (``docs/study_template.md``): :mod:`.scenario` (frozen scenario dataclasses,
the IMU as a :class:`mtcal.core.sensors.SensorSpec`, parameter defaults, builders),
:mod:`.error_model` (the hardware error model's priors, identified from Tables 1–4 and the
printed matrices), :mod:`.runs` (simulation runs), :mod:`.artifacts` (one producer per
table/figure, plus comparison rows), :mod:`.plots` (figures; imports matplotlib on call);
:mod:`.constrained` (the constrained-calibration question of notebook 40).
"""

from . import artifacts, constrained, error_model, runs, scenario
from .artifacts import *  # noqa: F401,F403
from .error_model import *  # noqa: F401,F403
from .runs import *  # noqa: F401,F403
from .scenario import *  # noqa: F401,F403

__all__ = ["artifacts", "constrained", "error_model", "runs", "scenario", "plots"]
__all__ += [n for m in (error_model, scenario, runs, artifacts) for n in m.__all__ if n not in __all__]


def __getattr__(name):
    if name == "plots":            # matplotlib only when a figure is asked for
        import importlib
        return importlib.import_module(f"{__name__}.plots")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
