"""Unit constants: multiply a value in the named unit to get SI / radians.

>>> round(2.0 * DEG_S, 12) == round(2.0 * 3.141592653589793 / 180.0, 12)
True
>>> 100 * UG  # 100 µg in m/s²
0.000980665
"""

from __future__ import annotations

import numpy as np

from mtcal.core.validate import STANDARD_GRAVITY_M_S2

__all__ = ["DEG", "DEG_S", "DEG_H", "DEG_RT_H", "ARCSEC", "G", "MG", "UG", "STANDARD_GRAVITY_M_S2"]

DEG = np.pi / 180.0            #: 1° in rad
DEG_S = DEG                    #: 1 °/s in rad/s
DEG_H = DEG / 3600.0           #: 1 °/h in rad/s
DEG_RT_H = DEG / 60.0          #: 1 °/√h in rad/√s (angle random walk)
ARCSEC = DEG / 3600.0          #: 1″ in rad
G = STANDARD_GRAVITY_M_S2      #: 1 g in m/s²
MG = 1e-3 * G                  #: 1 mg in m/s²
UG = 1e-6 * G                  #: 1 µg in m/s²
