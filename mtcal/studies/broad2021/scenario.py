"""broad2021 scenario: where the BROAD trials live, one trial's arrays, the settings of notebook 60.

BROAD (Laidig, Caruso, Cereatti, Seel, *Data* 6(7):72, 2021) ships IMU recordings with optical
ground truth; 14 of its 39 trials are in the repository's ``datasets/broad2021`` (licence and
citation in its README). :func:`load_trial` reads one trial file (``.mat`` or ``.h5``, through the one
low-level reader :func:`mtcal.core.arrayfile.read_arrays`) into a :class:`Trial` in SI units;
:func:`load_trials` reads the shipped ones with their BROAD groups (``trials.json``).

Settings (:class:`BroadScenario`, built once by :func:`scenario_from_parameters`):

* the 6D filters of notebook 50's bake-off and their gains (registry defaults; QNCF twice: the
  paper's settings and what ``mtcal attitude`` does by default);
* BROAD's chosen 9D parameters (``paper_data/broad2021_params.csv``, role ``input``): Madgwick
  β = 0.12 rad/s, Mahony K_p = 0.74 /s, K_i = 0.0012 /s²;
* the twin (:mod:`.error_model`): smoothing windows of the optical trajectory, the margin of the
  initial rest, local gravity, draws per trial.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mtcal.core.arrayfile import read_arrays
from mtcal.core.validate import merge_parameters, positive_int, positive_scalar
from mtcal.reporting import paper_numbers

__all__ = ["DATA_ENV", "data_dir", "Trial", "load_trial", "trial_from_arrays", "trial_names", "load_trials",
           "trial_groups", "trial_head", "GROUP_CATEGORIES", "FILTERS_6D", "BroadScenario", "PARAMETER_DEFAULTS",
           "scenario_from_parameters", "broad_parameters"]

#: Environment variable overriding the folder of the BROAD data (``trials/``, ``trials.json``, ``published/``).
DATA_ENV = "MTCAL_BROAD_DIR"
#: BROAD's group categories (``trials.json``) and the groups of each, in BROAD's order.
GROUP_CATEGORIES = {"motion": ("rotation", "translation", "combined"), "speed": ("slow", "fast"),
                    "breaks": ("no_breaks", "with_breaks"),
                    "disturbance": ("tapping", "vibration", "stationary_magnet", "attached_magnet")}
#: The 6D filters of the real-data bake-off (notebook 50's, QNCF at the paper's and the CLI's settings).
FILTERS_6D = ("qncf_paper", "qncf_cli", "mahony", "madgwick", "vqf", "basicvqf", "fusion")
_REPO_DATA = Path(__file__).resolve().parents[3] / "datasets" / "broad2021"
_ARRAYS = {"imu_gyr": 2, "imu_acc": 2, "imu_mag": 2, "opt_quat": 2, "opt_pos": 2, "movement": 1, "sampling_rate": 0}


def data_dir() -> Path:
    """The BROAD data folder: ``$MTCAL_BROAD_DIR``, else the repository's ``datasets/broad2021``.

    Raises
    ------
    FileNotFoundError
        The folder (or its ``trials.json``) is missing, naming where it was looked for.
    """
    env = os.environ.get(DATA_ENV)
    path = Path(env) if env else _REPO_DATA
    if not (path / "trials.json").is_file():
        raise FileNotFoundError(f"BROAD data not found in {path} (no trials.json); the repository ships it in "
                                f"datasets/broad2021 — set {DATA_ENV} to a folder holding trials.json, trials/ "
                                "and published/")
    return path


@dataclass(frozen=True)
class Trial:
    """One BROAD trial in SI units.

    Attributes
    ----------
    name : str
        Trial name (``"01_undisturbed_slow_rotation_A"``).
    gyro_rad_s, accel_m_s2, mag_uT : ndarray, shape (N, 3)
        IMU samples (rad/s, m/s², µT).
    opt_quat : ndarray, shape (N, 4)
        Optical IMU attitude, scalar-first, sensor → ENU; NaN rows where markers were lost.
    opt_pos_m : ndarray, shape (N, 3)
        Optical position (m); NaN rows where markers were lost.
    movement : ndarray of bool, shape (N,)
        BROAD's movement phase (errors are computed over it).
    fs_hz : float
        Sample rate (Hz).
    groups : tuple of str
        BROAD groups of the trial (``trials.json``); empty when unknown.
    """

    name: str
    gyro_rad_s: np.ndarray
    accel_m_s2: np.ndarray
    mag_uT: np.ndarray
    opt_quat: np.ndarray
    opt_pos_m: np.ndarray
    movement: np.ndarray
    fs_hz: float
    groups: tuple = field(default=())

    @property
    def dt_s(self) -> float:
        """Sample interval (s)."""
        return 1.0 / self.fs_hz

    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.gyro_rad_s.shape[0])


def trial_from_arrays(name: str, arrays: dict, groups=()) -> Trial:
    """A :class:`Trial` from BROAD's named arrays (``imu_gyr``, ``imu_acc``, ``imu_mag``, ``opt_quat``,
    ``opt_pos``, ``movement``, ``sampling_rate``), validated once here.

    >>> n = 10
    >>> t = trial_from_arrays("x", {"imu_gyr": np.zeros((n, 3)), "imu_acc": np.tile([0, 0, 9.81], (n, 1)),
    ...     "imu_mag": np.ones((n, 3)), "opt_quat": np.tile([1.0, 0, 0, 0], (n, 1)), "opt_pos": np.zeros((n, 3)),
    ...     "movement": np.ones(n), "sampling_rate": np.array(100.0)})
    >>> t.n, t.dt_s, bool(t.movement.all())
    (10, 0.01, True)
    """
    missing = [k for k in _ARRAYS if k not in arrays]
    if missing:
        raise ValueError(f"trial {name!r}: arrays {missing} missing (a BROAD trial holds {sorted(_ARRAYS)})")
    arr = {k: np.asarray(arrays[k], dtype=float) for k in _ARRAYS}
    n = arr["imu_gyr"].shape[0] if arr["imu_gyr"].ndim == 2 else -1
    for k, nd in _ARRAYS.items():
        want = {2: (n, 4 if k == "opt_quat" else 3), 1: (n,), 0: ()}[nd]
        if arr[k].shape != want:
            raise ValueError(f"trial {name!r}: {k} must have shape {want}, got {arr[k].shape}")
    for k in ("imu_gyr", "imu_acc", "imu_mag"):
        if not np.all(np.isfinite(arr[k])):
            raise ValueError(f"trial {name!r}: {k} holds non-finite values")
    fs = positive_scalar(float(arr["sampling_rate"]), "sampling_rate")
    return Trial(name=str(name), gyro_rad_s=arr["imu_gyr"], accel_m_s2=arr["imu_acc"], mag_uT=arr["imu_mag"],
                 opt_quat=arr["opt_quat"], opt_pos_m=arr["opt_pos"], movement=arr["movement"] > 0.5, fs_hz=fs,
                 groups=tuple(groups))


def trial_head(trial: Trial, n_samples: int | None) -> Trial:
    """The first ``n_samples`` of a trial (the whole trial for None or a longer count): a CI-size slice."""
    if n_samples is None or n_samples >= trial.n:
        return trial
    n = positive_int(n_samples, "n_samples")
    return Trial(trial.name, trial.gyro_rad_s[:n], trial.accel_m_s2[:n], trial.mag_uT[:n], trial.opt_quat[:n],
                 trial.opt_pos_m[:n], trial.movement[:n], trial.fs_hz, trial.groups)


def load_trial(path, groups=()) -> Trial:
    """One BROAD trial file (``.mat`` v5/v7.3 or ``.h5``/``.hdf5``) as a :class:`Trial` (name = file stem)."""
    p = Path(path)
    return trial_from_arrays(p.stem, read_arrays(p), groups)


def _info(folder: Path) -> dict:
    with open(folder / "trials.json", encoding="utf-8") as f:
        return json.load(f)


def _trial_files(folder: Path) -> dict[str, Path]:
    """``{name: file}`` of the trials in ``folder/trials`` (.mat, else .hdf5/.h5 — BROAD ships both, same data)."""
    files: dict[str, Path] = {}
    for suffix in (".h5", ".hdf5", ".mat"):          # later suffixes win: .mat when both exist
        files.update({p.stem: p for p in (folder / "trials").glob(f"*{suffix}")})
    return dict(sorted(files.items()))


def trial_names(folder=None) -> list[str]:
    """Names of the trials in ``trials/`` (``.mat``, ``.hdf5`` or ``.h5`` files), sorted."""
    folder = data_dir() if folder is None else Path(folder)
    return list(_trial_files(folder))


def trial_groups(folder=None) -> dict[str, tuple]:
    """BROAD groups of every trial of ``trials.json`` (all 39), by name."""
    folder = data_dir() if folder is None else Path(folder)
    return {k: tuple(v["groups"]) for k, v in _info(folder)["trials"].items()}


def load_trials(names=None, folder=None) -> list[Trial]:
    """The shipped trials (or ``names`` of them), in name order, with their groups."""
    folder = data_dir() if folder is None else Path(folder)
    available = trial_names(folder)
    names = available if names is None else list(names)
    bad = [n for n in names if n not in available]
    if bad:
        raise ValueError(f"trials {bad} are not shipped; available: {available}")
    groups = trial_groups(folder)
    files = _trial_files(folder)
    return [load_trial(files[n], groups.get(n, ())) for n in names]


def broad_parameters() -> dict[str, float]:
    """BROAD's chosen 9D parameters (its TAGP setting), from ``paper_data/broad2021_params.csv`` (role input).

    >>> broad_parameters()
    {'madgwick_beta': 0.12, 'mahony_kp': 0.74, 'mahony_ki': 0.0012}
    """
    df = paper_numbers.training("broad2021")["broad2021_params"]
    return {f"{r.filter}_{r.parameter}": float(r.value) for r in df.itertuples()}


@dataclass(frozen=True)
class BroadScenario:
    """Resolved settings of notebook 60 (SI units).

    Attributes
    ----------
    trials : tuple of str
        Trials to run (default: every shipped one).
    filters : tuple of str
        6D filters (:data:`FILTERS_6D`).
    twin_filters : tuple of str
        6D filters the twin predicts (the fast ones; Fusion's per-sample loop is left out for cost).
    n_draws : int
        Twin draws per trial and filter.
    max_samples : int or None
        Keep only the first samples of each trial (CI size); None: whole trials.
    rest_margin_s : float
        Samples this close to the first movement sample are not used as the initial rest (s).
    smooth_quat_s, smooth_pos_s : float
        Savitzky–Golay windows of the optical attitude and position (s) for the twin's truth.
    local_gravity_m_s2 : float
        Gravity at the recording site (Berlin, 52.5° N: 9.8128 m/s², normal gravity formula) —
        the reference of the accelerometer's norm offset at rest.
    madgwick_beta, mahony_kp, mahony_ki : float
        BROAD's chosen 9D parameters (input).
    """

    trials: tuple
    filters: tuple = FILTERS_6D
    twin_filters: tuple = ("qncf_paper", "qncf_cli", "mahony", "madgwick", "vqf", "basicvqf")
    n_draws: int = 8
    max_samples: int | None = None
    rest_margin_s: float = 0.5
    smooth_quat_s: float = 0.1
    smooth_pos_s: float = 0.2
    local_gravity_m_s2: float = 9.8128
    madgwick_beta: float = 0.12
    mahony_kp: float = 0.74
    mahony_ki: float = 0.0012


#: The notebook's parameters cell (``None`` trials = every shipped trial).
PARAMETER_DEFAULTS = {"trials": None, "filters": list(FILTERS_6D), "n_draws": 8, "max_samples": None,
                      "rest_margin_s": 0.5, "smooth_quat_s": 0.1, "smooth_pos_s": 0.2}


def scenario_from_parameters(**params) -> BroadScenario:
    """Validate the parameters cell once and resolve it (see :class:`BroadScenario`).

    >>> sc = scenario_from_parameters(trials=["01_undisturbed_slow_rotation_A"], n_draws=3)
    >>> sc.n_draws, sc.madgwick_beta, sc.trials
    (3, 0.12, ('01_undisturbed_slow_rotation_A',))
    >>> scenario_from_parameters(n_draws=0)
    Traceback (most recent call last):
    ...
    ValueError: n_draws must be >= 1, got 0
    """
    p = merge_parameters(params, PARAMETER_DEFAULTS, what="broad2021 parameter")
    available = trial_names()
    trials = tuple(available if p["trials"] is None else p["trials"])
    bad = [t for t in trials if t not in available]
    if bad or not trials:
        raise ValueError(f"trials must be shipped BROAD trials {available}, got {bad or trials}")
    filters = tuple(p["filters"])
    bad = [f for f in filters if f not in FILTERS_6D]
    if bad or not filters:
        raise ValueError(f"filters must be among {FILTERS_6D}, got {bad or filters}")
    n_draws = positive_int(p["n_draws"], "n_draws")
    max_samples = None if p["max_samples"] is None else positive_int(p["max_samples"], "max_samples")
    chosen = broad_parameters()
    twin = tuple(f for f in BroadScenario.twin_filters if f in filters)
    return BroadScenario(trials=trials, filters=filters, twin_filters=twin, n_draws=n_draws, max_samples=max_samples,
                         rest_margin_s=positive_scalar(p["rest_margin_s"], "rest_margin_s"),
                         smooth_quat_s=positive_scalar(p["smooth_quat_s"], "smooth_quat_s"),
                         smooth_pos_s=positive_scalar(p["smooth_pos_s"], "smooth_pos_s"),
                         madgwick_beta=chosen["madgwick_beta"], mahony_kp=chosen["mahony_kp"],
                         mahony_ki=chosen["mahony_ki"])
