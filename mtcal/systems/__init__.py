"""Systems: the papers' measurement procedures over plain arrays.

A procedure here strings the methods and filters together the way a paper's
measurement does (attitude → rests → fit → plausibility gates → result), and is
called identically by the studies, the sweeps and the CLI, so the notebooks
validate the very code path the ``mtcal`` command ships. A procedure takes one
frozen config plus the arrays, validates them once at its public edge and calls
the methods and filters below, which trust their inputs (each states its
Preconditions). It imports from ``core``, ``methods`` and ``filters`` only;
``studies``, ``sweep`` and ``cli`` import it.

* :mod:`~mtcal.systems.installation` — six-position installation-error
  calibration (wang2023cja §3.2, Eq 1, 10, 13–15), a Monte Carlo session's measurement
  (:func:`~mtcal.systems.installation.measure_session`) and its application (Eq 10)
* :mod:`~mtcal.systems.surface_angle` — wang2022sensors movable-surface angle:
  rotation axis from rests (Eq 23), ZVD-switched RAMS EKF with restart after clipping
* :mod:`~mtcal.systems.attitude` — attitude of a recorded log: the paper's QNCF set up from its
  rests and noise (wang2023cja §3.1) or another filter, as ``mtcal attitude`` and the real-data study run it
* :mod:`~mtcal.systems.rests` — the rests of a log and the levels the detector measured, as
  ``mtcal rests`` and every command reading raw data find them
* :mod:`~mtcal.systems.plausibility` — checks of a record before a procedure trusts
  it (units, time base, clipping, gyro axis)
"""

from typing import TYPE_CHECKING

from mtcal.core.lazy import lazy_attributes

if TYPE_CHECKING:  # the eager imports, for type checkers and tests/test_import_graph.py
    from mtcal.systems import attitude, installation, plausibility, rests, surface_angle
    from mtcal.systems.attitude import AttitudeConfig, attitude_record, estimate_attitude
    from mtcal.systems.rests import RestsConfig, find_rests
    from mtcal.systems.surface_angle import (AxisConfig, AxisRecordConfig, SurfaceAngleBatch, SurfaceAngleConfig,
                                             SurfaceBatchConfig, SurfaceRecordConfig, estimate_surface_axis,
                                             surface_angle_batch, surface_angle_record, surface_axis_record)
    from mtcal.systems.installation import (CalibratedAttitude, InstallationCalibration, InstallationConfig,
                                            InstallationRefused, apply_installation, calibrate_installation,
                                            detect_rests, verify_installation, calibrate_record, apply_record,
                                            RecordCalibration, RecordApplication, RecordRefused, RefusalDiagnosis,
                                            SessionPiece, SessionMeasurement, measure_session)

__all__ = ["attitude", "installation", "plausibility", "rests", "surface_angle", "InstallationCalibration",
           "InstallationConfig", "InstallationRefused", "verify_installation", "calibrate_record", "apply_record",
           "RecordCalibration", "RecordApplication", "RecordRefused", "RefusalDiagnosis", "SessionPiece",
           "SessionMeasurement", "measure_session", "CalibratedAttitude", "calibrate_installation", "apply_installation", "detect_rests", "AttitudeConfig",
           "estimate_attitude", "RestsConfig", "find_rests", "AxisConfig", "SurfaceAngleConfig", "SurfaceBatchConfig",
           "SurfaceAngleBatch", "surface_angle_batch", "estimate_surface_axis", "attitude_record", "AxisRecordConfig",
           "surface_axis_record", "SurfaceRecordConfig", "surface_angle_record"]

#: Submodules, loaded on first attribute access (``import mtcal`` stays light for the CLI).
_SUBMODULES = ('attitude', 'installation', 'plausibility', 'rests', 'surface_angle')
#: Re-exported name → submodule defining it (imported on first access).
_EXPORTS = {
    "CalibratedAttitude": "installation", "InstallationCalibration": "installation",
    "apply_installation": "installation", "calibrate_installation": "installation", "detect_rests": "installation",
    "InstallationConfig": "installation", "InstallationRefused": "installation", "verify_installation": "installation",
    "calibrate_record": "installation", "apply_record": "installation", "RecordCalibration": "installation",
    "RecordApplication": "installation", "RecordRefused": "installation", "RefusalDiagnosis": "installation",
    "SessionPiece": "installation", "SessionMeasurement": "installation", "measure_session": "installation",
    "AttitudeConfig": "attitude", "estimate_attitude": "attitude", "RestsConfig": "rests", "find_rests": "rests",
    "AxisConfig": "surface_angle", "SurfaceAngleConfig": "surface_angle", "SurfaceBatchConfig": "surface_angle",
    "SurfaceAngleBatch": "surface_angle", "surface_angle_batch": "surface_angle",
    "estimate_surface_axis": "surface_angle", "attitude_record": "attitude", "AxisRecordConfig": "surface_angle",
    "surface_axis_record": "surface_angle", "SurfaceRecordConfig": "surface_angle",
    "surface_angle_record": "surface_angle",
}

__getattr__, __dir__ = lazy_attributes(globals(), _SUBMODULES, _EXPORTS)
