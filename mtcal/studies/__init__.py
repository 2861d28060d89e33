"""One study package per paper: its scenario dataclasses (the paper's defaults), runs,
and the functions that compute each table and figure.

* :mod:`mtcal.studies.wang2023cja` — installation-error calibration (Chin. J. Aeronaut. 2023)
* :mod:`mtcal.studies.tan2022` — large-angle pitch/roll (J. Terahertz Sci. Electron. Inf. Technol. 2022)
* :mod:`mtcal.studies.wang2022sensors` — movable-surface angle (Sensors 2022)
* :mod:`mtcal.studies.broad2021` — BROAD real trials with optical ground truth (Data 2021)
* :mod:`mtcal.studies.conventions` — notebook 00: the papers' conventions and errata, computed

Study packages are imported on demand (``from mtcal.studies import tan2022``).
"""

__all__ = ["wang2023cja", "tan2022", "wang2022sensors", "broad2021", "conventions"]
