"""The papers' measurement procedures as functions over plain arrays (one per step and one per system).

Modules
-------
plausibility
    Checks of a record before a procedure trusts it (units, time base, clipping, gyro axis).
surface_angle
    wang2022sensors movable-surface angle: rotation axis from rests (Eq 23), ZVD-switched RAMS EKF.
"""

from mtcal.systems import plausibility, surface_angle

__all__ = ["plausibility", "surface_angle"]
