"""mtcal — attitude estimation and IMU calibration, reproduced from three papers.

Modules (one concept each): :mod:`mtcal.rotations` (conventions),
:mod:`mtcal.simulate` (IMU error model), :mod:`mtcal.profiles` (motion
profiles), :mod:`mtcal.metrics` (RMSE, MaxAE, Allan deviation),
:mod:`mtcal.paper` (the papers' numbers), :mod:`mtcal.report` (notebook output).
"""

__version__ = "0.1.0"
