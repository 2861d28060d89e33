import json
import os
import subprocess
import sys

import numpy as np
import pytest

from mtcal.core import metrics, philox, profiles, rotations, simulate
from mtcal.core.rng import spawn_philox_key
from mtcal.core.simulate import ImuErrorModel, SensorErrors, Trajectory

G = 9.80665


@pytest.fixture
def turntable():
    wp = np.radians([[0, 0, 0], [8, 0, 0], [0, -12, 0], [0, 23, 30], [0, 0, -90]])
    return profiles.trajectory_from_euler_zxy(profiles.step_schedule(wp, np.radians(10), 1.0, 500))


def test_noise_free_gyro_integrates_to_truth(turntable):
    rec = simulate.simulate_imu(turntable)
    q = simulate.integrate_gyro(turntable.q_wb[0], rec.gyro_rad_s, turntable.dt_s)
    assert np.max(rotations.quat_angle_between(q, turntable.q_wb)) < 1e-9


def test_static_accel_is_rotated_gravity(turntable):
    rec = simulate.simulate_imu(turntable)
    c_wb = rotations.quat_to_matrix(turntable.q_wb)
    expected = np.einsum("nji,j->ni", c_wb, [0.0, 0.0, G])
    np.testing.assert_allclose(rec.accel_m_s2, expected, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(rec.accel_m_s2, axis=1), G, atol=1e-12)


def test_mounting_rotates_sensor_outputs(turntable):
    q_bs = rotations.quat_from_euler_zxy(0.02, -0.01, 0.03)
    rec = simulate.simulate_imu(turntable, ImuErrorModel(q_mount=tuple(q_bs)))
    q = simulate.integrate_gyro(rec.q_ws_true[0], rec.gyro_rad_s, turntable.dt_s)
    assert np.max(rotations.quat_angle_between(q, rec.q_ws_true)) < 1e-9
    c_ws = rotations.quat_to_matrix(rec.q_ws_true)
    np.testing.assert_allclose(rec.accel_m_s2, np.einsum("nji,j->ni", c_ws, [0, 0, G]), atol=1e-12)


def test_lever_arm_gives_centripetal_and_tangential():
    prof = profiles.constant_rate(0.0, 2.0, 2.0, 1000.0)
    traj = profiles.fixed_axis_trajectory(prof, [0.0, 0.0, 1.0], lever_arm_b_m=[0.5, 0.0, 0.0])
    rec = simulate.simulate_imu(traj)
    # rotating about z at 2 rad/s: centripetal ω²r = 2 m/s² toward the axis (−x body), gravity on z
    np.testing.assert_allclose(rec.accel_m_s2[10], [-2.0, 0.0, G], atol=1e-9)
    np.testing.assert_allclose(rec.gyro_rad_s[10], [0, 0, 2.0], atol=1e-9)


def test_fixed_axis_static_measurement_model():
    """wang2022sensors: a = R(θ, v)ᵀ ā0 for the static part."""
    v = np.array([0.1734, 0.9835, 0.0523])
    v /= np.linalg.norm(v)
    prof = profiles.step_schedule(np.radians([0.0, 40.0, -100.0]), np.radians(30), 1.0, 200)
    traj = profiles.fixed_axis_trajectory(prof, v, lever_arm_b_m=[0.1, 0.2, 0.0])
    rec = simulate.simulate_imu(traj)
    a0 = np.array([0.0, 0.0, G])
    for sl in prof.hold_slices():
        k = sl.start + 5
        expected = rotations.axis_angle_matrix(prof.angle_rad[k, 0], v).T @ a0
        np.testing.assert_allclose(rec.accel_m_s2[k], expected, atol=1e-9)


def test_white_noise_std_scales_with_sample_rate(rng):
    t = np.arange(20000) / 1000.0
    traj = Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-3))
    rec = simulate.simulate_imu(traj, model, rng, trials=4)
    assert rec.gyro_rad_s.shape == (4, t.size, 3)
    std = np.std(rec.gyro_rad_s)
    assert std == pytest.approx(1e-3 * np.sqrt(1000.0), rel=0.02)


def test_turn_on_bias_scale_and_warmup(rng):
    t = np.arange(2000) / 100.0
    traj = Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))
    model = ImuErrorModel(gyro=SensorErrors(bias=(1e-3, 0, 0), bias_sigma=1e-4, warmup_bias=2e-3,
                                            warmup_tau_s=5.0),
                          accel=SensorErrors(scale_factor=(0, 0, 1e-3)))
    rec = simulate.simulate_imu(traj, model, rng, trials=500)
    turn_on = rec.gyro_rad_s[:, -1, :] - np.array([1e-3, 0, 0]) - 2e-3 * np.exp(-t[-1] / 5.0)
    assert np.std(turn_on) == pytest.approx(1e-4, rel=0.1)
    np.testing.assert_allclose(rec.accel_m_s2[0, 0], [0, 0, G * 1.001])
    drop = rec.gyro_rad_s[:, 0, 1] - rec.gyro_rad_s[:, -1, 1]
    np.testing.assert_allclose(drop, 2e-3 * (1 - np.exp(-t[-1] / 5.0)), atol=1e-12)


def test_same_seed_same_output_and_sources_independent():
    t = np.arange(1000) / 100.0
    traj = Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))
    a = ImuErrorModel(gyro=SensorErrors(noise_density=1e-3))
    b = ImuErrorModel(gyro=SensorErrors(noise_density=1e-3, bias_random_walk=1e-4))
    ra = simulate.simulate_imu(traj, a, np.random.default_rng(7), trials=2)
    ra2 = simulate.simulate_imu(traj, a, np.random.default_rng(7), trials=2)
    rb = simulate.simulate_imu(traj, b, np.random.default_rng(7), trials=2)
    np.testing.assert_array_equal(ra.gyro_rad_s, ra2.gyro_rad_s)
    # adding a random walk leaves the white-noise draws unchanged (common random numbers)
    diff = rb.gyro_rad_s - ra.gyro_rad_s
    assert np.all(np.abs(np.diff(diff, axis=1)) < 1e-4 * np.sqrt(0.01) * 6)


def test_quantization_and_vibration(rng):
    t = np.arange(1000) / 1000.0
    traj = Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))
    model = ImuErrorModel(accel=SensorErrors(quantization=0.01, vibration_amplitude=(0, 0, 2.0),
                                             vibration_freq_hz=50.0))
    rec = simulate.simulate_imu(traj, model, rng)
    np.testing.assert_allclose(rec.accel_m_s2 / 0.01, np.round(rec.accel_m_s2 / 0.01), atol=1e-9)
    assert np.ptp(rec.accel_m_s2[:, 2]) == pytest.approx(4.0, abs=0.05)


def test_allan_recovers_configured_noise(rng):
    """White noise density at τ = 1 s and rate random walk within 10 % (issue #3, item 6)."""
    fs = 10.0  # 8 h records: long enough for the τ > 100 s random-walk branch
    t = np.arange(int(8 * 3600 * fs)) / fs
    traj = Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))
    n_density, k_rrw = 2e-4, 2e-5  # σ_A curves cross at τ = √3 N/K ≈ 17 s
    model = ImuErrorModel(gyro=SensorErrors(noise_density=n_density, bias_random_walk=k_rrw))
    rec = simulate.simulate_imu(traj, model, rng, trials=8)
    records = np.moveaxis(rec.gyro_rad_s, -1, 1)  # 8 trials × 3 axes = 24 independent records
    taus, adev = metrics.allan_deviation(records, 1.0 / fs)
    fit = metrics.fit_allan_noise(taus, adev, flat_term=False)
    assert fit["N"] == pytest.approx(n_density, rel=0.10)
    assert fit["K"] == pytest.approx(k_rrw, rel=0.10)


def test_gauss_markov_bias_instability_is_stationary(rng):
    t = np.arange(5000) / 10.0
    traj = Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))
    model = ImuErrorModel(gyro=SensorErrors(bias_instability=1e-4, bias_instability_tau_s=20.0))
    rec = simulate.simulate_imu(traj, model, rng, trials=400)
    std_start = np.std(rec.gyro_rad_s[:, 0, :])
    std_end = np.std(rec.gyro_rad_s[:, -1, :])
    assert std_start == pytest.approx(1e-4, rel=0.1)
    assert std_end == pytest.approx(1e-4, rel=0.1)


@pytest.mark.parametrize("kwargs,match", [
    (dict(time_s=[0.0, 0.1, 0.1], q_wb=np.tile([1.0, 0, 0, 0], (3, 1))), "strictly increasing"),
    (dict(time_s=[0.0, 0.1, 0.2], q_wb=np.tile([1.0, 0, 0, 0], (2, 1))), "must have shape"),
    (dict(time_s=[0.0, 0.1, np.nan], q_wb=np.tile([1.0, 0, 0, 0], (3, 1))), "finite"),
    (dict(time_s=[0.0, 0.1, 0.25], q_wb=np.tile([1.0, 0, 0, 0], (3, 1))), "uniformly sampled"),
    (dict(time_s=[0.0, 0.1, 0.2], q_wb=np.tile([2.0, 0, 0, 0], (3, 1))), "unit quaternions"),
])
def test_trajectory_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Trajectory(**kwargs)


def test_bad_models_raise():
    with pytest.raises(ValueError, match="noise_density must be >= 0"):
        SensorErrors(noise_density=-1.0)
    with pytest.raises(ValueError, match="wrong unit"):
        ImuErrorModel(accel=SensorErrors(bias=9.81))
    with pytest.raises(ValueError, match="degrees passed as radians"):
        ImuErrorModel(gyro=SensorErrors(bias=(5.0, 0, 0)))
    with pytest.raises(ValueError, match="misalignment must be 3x3"):
        SensorErrors(misalignment=((0.0, 0.0), (0.0, 0.0)))
    traj = Trajectory([0.0, 0.1, 0.2], np.tile([1.0, 0, 0, 0], (3, 1)))
    with pytest.raises(ValueError, match="rng must be"):
        simulate.simulate_imu(traj, ImuErrorModel(gyro=SensorErrors(noise_density=1e-3)))
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        simulate.simulate_imu(traj, rng=42)
    with pytest.raises(ValueError, match="trials must be >= 1"):
        simulate.simulate_imu(traj, rng=np.random.default_rng(0), trials=0)


@pytest.mark.parametrize("chunk", [1, 97, 256, 1000, 5000])
def test_stream_is_chunk_size_independent(chunk):
    """Same seed ⇒ same numbers whatever the chunk size (issue #7)."""
    wp = np.radians([[0, 0, 0], [8, 0, 0], [0, -12, 30]])
    traj = profiles.trajectory_from_euler_zxy(profiles.step_schedule(wp, np.radians(20), 0.5, 1000))
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-4, bias_sigma=1e-4, bias_random_walk=1e-5,
                                            bias_instability=1e-5, bias_instability_tau_s=2.0),
                          accel=SensorErrors(noise_density=1e-3, vibration_amplitude=0.1, vibration_freq_hz=30.0,
                                             quantization=1e-4))
    whole = simulate.simulate_imu(traj, model, np.random.default_rng(3), trials=3)
    parts = list(simulate.ImuStream(traj, model, np.random.default_rng(3), trials=3).chunks(chunk))
    np.testing.assert_array_equal(np.concatenate([p.gyro_rad_s for p in parts], axis=1), whole.gyro_rad_s)
    np.testing.assert_array_equal(np.concatenate([p.accel_m_s2 for p in parts], axis=1), whole.accel_m_s2)
    np.testing.assert_array_equal(np.concatenate([p.time_s for p in parts]), whole.time_s)


@pytest.mark.parametrize("engine", ["numba", "numpy"])
def test_stream_recycles_only_chunks_nobody_holds(engine):
    """Output buffers are reused once dropped (no fresh 24 MB page faults per chunk), never while a chunk,
    or a view of one of its arrays, is still held: held data stays what it was."""
    wp = np.radians([[0, 0, 0], [8, 0, 0]])
    traj = profiles.trajectory_from_euler_zxy(profiles.step_schedule(wp, np.radians(20), 0.3, 400))
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-4, bias_instability=1e-5, quantization=1e-6),
                          accel=SensorErrors(noise_density=1e-3))
    whole = simulate.simulate_imu(traj, model, np.random.default_rng(5), trials=2, engine=engine)
    stream = simulate.ImuStream(traj, model, np.random.default_rng(5), trials=2, engine=engine)
    seen, kept, views = set(), [], []
    for i, chunk in enumerate(stream.chunks(50)):
        seen.add(id(chunk.gyro_rad_s.base if chunk.gyro_rad_s.base is not None else chunk.gyro_rad_s))
        if i == 1:
            kept.append(chunk)                         # a whole chunk held
        if i == 2:
            views.append((i, chunk.accel_m_s2[:, 10:20]))  # only a view of one array held
        del chunk
    n_chunks = -(-len(traj) // 50)
    assert n_chunks >= 6 and len(seen) < 2 * n_chunks    # buffers were reused
    np.testing.assert_array_equal(kept[0].gyro_rad_s, whole.gyro_rad_s[:, 50:100])
    np.testing.assert_array_equal(kept[0].accel_m_s2, whole.accel_m_s2[:, 50:100])
    np.testing.assert_array_equal(views[0][1], whole.accel_m_s2[:, 110:120])


def test_stream_single_pass_and_bad_chunk():
    traj = Trajectory(np.arange(10) / 10.0, np.tile([1.0, 0, 0, 0], (10, 1)))
    stream = simulate.ImuStream(traj)
    assert sum(len(c.time_s) for c in stream.chunks(3)) == 10
    with pytest.raises(ValueError, match="iterated once"):
        next(stream.chunks(3))
    with pytest.raises(ValueError, match="chunk_samples must be >= 1"):
        next(simulate.ImuStream(traj).chunks(0))


def test_apply_sensor_errors_matches_simulator_and_takes_per_trial_truth():
    wp = np.radians([[0, 0, 0], [8, 0, 0]])
    traj = profiles.trajectory_from_euler_zxy(profiles.step_schedule(wp, np.radians(20), 0.3, 200))
    errs = SensorErrors(noise_density=1e-3, bias_sigma=1e-3, bias_random_walk=1e-4)
    rec = simulate.simulate_imu(traj, ImuErrorModel(gyro=errs), np.random.default_rng(5), trials=2)
    truth = np.stack([rec.gyro_true_rad_s, 2 * rec.gyro_true_rad_s])
    out = simulate.apply_sensor_errors(errs, truth, traj.time_s, np.random.default_rng(5))
    assert out.shape == truth.shape
    noise = out - truth
    assert np.std(noise[:, :, 0]) > 0
    single = simulate.apply_sensor_errors(SensorErrors(bias=0.5), rec.accel_true_m_s2, traj.time_s)
    np.testing.assert_allclose(single, rec.accel_true_m_s2 + 0.5)
    with pytest.raises(ValueError, match="rng must be"):
        simulate.apply_sensor_errors(errs, truth, traj.time_s)
    with pytest.raises(ValueError, match="samples on axis -2"):
        simulate.apply_sensor_errors(errs, truth[:, :-1], traj.time_s, np.random.default_rng(0))


_EVERY_SOURCE = SensorErrors(bias=(1e-3, 0.0, 2e-3), bias_sigma=1e-4, noise_density=1e-4, bias_random_walk=1e-5,
                             bias_instability=1e-5, bias_instability_tau_s=3.0, warmup_bias=(1e-3, 2e-3, 0.0),
                             warmup_tau_s=2.0, scale_factor=(1e-3, 0.0, -2e-3),
                             misalignment=((0, 1e-3, 0), (2e-3, 0, 0), (0, 0, 0)), quantization=1e-5,
                             vibration_amplitude=(1e-3, 0.0, 1e-3), vibration_freq_hz=33.0)


@pytest.mark.parametrize("chunk", [1, 97, 256, 1000])
def test_compiled_engine_is_bit_identical_to_numpy_reference(chunk):
    """The numba engine draws the same Philox streams and adds the terms in the same order (every source on);
    the numpy reference is chunked like the kernel except for chunk 1 (there it runs the whole record: slow)."""
    wp = np.radians([[0, 0, 0], [8, 0, 0], [0, -12, 30]])
    traj = profiles.trajectory_from_euler_zxy(profiles.step_schedule(wp, np.radians(20), 0.4, 1000))
    model = ImuErrorModel(gyro=_EVERY_SOURCE, accel=SensorErrors(noise_density=1e-3, bias_random_walk=1e-4,
                                                                bias_instability=1e-4, quantization=1e-4),
                          time_since_power_on_s=1.0)
    out = {}
    for engine in ("numba", "numpy"):
        size = chunk if engine == "numba" or chunk > 1 else len(traj)
        parts = list(simulate.ImuStream(traj, model, np.random.default_rng(9), trials=3, engine=engine).chunks(size))
        out[engine] = [np.concatenate([getattr(p, k) for p in parts], axis=1) for k in ("gyro_rad_s", "accel_m_s2")]
    for fast, ref in zip(out["numba"], out["numpy"]):
        np.testing.assert_array_equal(fast, ref)
    truth = np.stack([np.zeros((len(traj), 3)), np.ones((len(traj), 3))])  # per-trial truth
    fast, ref = (simulate.apply_sensor_errors(_EVERY_SOURCE, truth, traj.time_s, np.random.default_rng(2), engine=e)
                 for e in ("numba", "numpy"))
    np.testing.assert_array_equal(fast, ref)
    with pytest.raises(ValueError, match="engine must be one of"):
        simulate.simulate_imu(traj, engine="fortran")


def _static(n, fs):
    t = np.arange(n) / fs
    return Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))


def test_white_noise_is_the_documented_philox_stream():
    """Key layout: sample k of trial t, axis j = lane k % 2 of counter (k // 2, t, stream word, 0)."""
    fs = 100.0
    traj = _static(301, fs)
    model = ImuErrorModel(gyro=SensorErrors(noise_density=np.sqrt(1 / fs)))   # per-sample σ = 1
    rec = simulate.simulate_imu(traj, model, np.random.default_rng(21), trials=2, trial_ids=[4, 9])
    key = spawn_philox_key(np.random.default_rng(21))
    for i, tid in enumerate((4, 9)):
        for j in range(3):
            z = philox.standard_normals(301, key=key, c1=tid, c2=philox.stream_word(0, philox.SOURCE_IDS["white"], j))
            np.testing.assert_array_equal(rec.gyro_rad_s[i, :, j], z)


def test_trial_subsets_get_the_same_numbers():
    """Trial t's numbers do not depend on which other trials run (every source on)."""
    traj = _static(700, 200.0)
    model = ImuErrorModel(gyro=_EVERY_SOURCE, accel=SensorErrors(noise_density=1e-3, bias_sigma=1e-3))
    full = simulate.simulate_imu(traj, model, np.random.default_rng(4), trials=6)
    sub = simulate.simulate_imu(traj, model, np.random.default_rng(4), trials=2, trial_ids=[5, 2])
    np.testing.assert_array_equal(sub.gyro_rad_s, full.gyro_rad_s[[5, 2]])
    np.testing.assert_array_equal(sub.accel_m_s2, full.accel_m_s2[[5, 2]])
    parts = list(simulate.ImuStream(traj, model, np.random.default_rng(4), trial_ids=range(3, 6)).chunks(333))
    np.testing.assert_array_equal(np.concatenate([p.gyro_rad_s for p in parts], axis=1), full.gyro_rad_s[3:])
    one = simulate.simulate_imu(traj, model, np.random.default_rng(4), trial_ids=[1])
    np.testing.assert_array_equal(one.gyro_rad_s[0], full.gyro_rad_s[1])
    truth = np.zeros((2, 700, 3))
    a = simulate.apply_sensor_errors(_EVERY_SOURCE, truth, traj.time_s, np.random.default_rng(8))
    b = simulate.apply_sensor_errors(_EVERY_SOURCE, truth[:1], traj.time_s, np.random.default_rng(8), trial_ids=[1])
    np.testing.assert_array_equal(b[0], a[1])


@pytest.mark.parametrize("block", [1, 2, 7, 4096])
def test_kernel_block_size_does_not_change_numbers(block):
    traj = _static(1001, 500.0)
    model = ImuErrorModel(gyro=_EVERY_SOURCE)
    ref = simulate.simulate_imu(traj, model, np.random.default_rng(6), trials=3)
    parts = list(simulate.ImuStream(traj, model, np.random.default_rng(6), trials=3, block_samples=block).chunks(77))
    np.testing.assert_array_equal(np.concatenate([p.gyro_rad_s for p in parts], axis=1), ref.gyro_rad_s)


_THREAD_SCRIPT = """
import hashlib, json, numpy as np, numba
from mtcal.core import philox, simulate
from tests.core.test_simulate import _EVERY_SOURCE, _static
traj = _static(6000, 1000.0)   # 37 trials x 6000 samples: the trial-parallel kernel (with 2 threads)
model = simulate.ImuErrorModel(gyro=_EVERY_SOURCE, accel=simulate.SensorErrors(noise_density=1e-3, bias_sigma=1e-3))
h = hashlib.sha256()
for chunk in (6000, 251):
    for c in simulate.ImuStream(traj, model, np.random.default_rng(12), trials=37).chunks(chunk):
        h.update(c.gyro_rad_s.tobytes()); h.update(c.accel_m_s2.tobytes())
h.update(philox.standard_normals(100001, key=(3, 4)).tobytes())
print(json.dumps({"threads": numba.get_num_threads(), "sha": h.hexdigest()}))
"""


def test_bit_identical_for_one_and_two_threads():
    """The same numbers with NUMBA_NUM_THREADS=1 and 2 (subprocesses; chunkings inside)."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = []
    for threads in ("1", "2"):
        env = dict(os.environ, NUMBA_NUM_THREADS=threads, PYTHONPATH=os.pathsep.join(
            [root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
        res = subprocess.run([sys.executable, "-c", _THREAD_SCRIPT], cwd=root, env=env, capture_output=True,
                             text=True, check=True)
        out.append(json.loads(res.stdout.strip().splitlines()[-1]))
    assert [o["threads"] for o in out] == [1, 2]
    assert out[0]["sha"] == out[1]["sha"]


def test_parallel_and_serial_kernels_agree(monkeypatch):
    traj = _static(2000, 1000.0)
    model = ImuErrorModel(gyro=_EVERY_SOURCE, accel=SensorErrors(noise_density=1e-3, bias_instability=1e-4))
    out = []
    for min_work in (0, 10 ** 12):   # always / never the trial-parallel kernel
        monkeypatch.setattr(simulate, "PARALLEL_MIN_WORK", min_work)
        rec = simulate.simulate_imu(traj, model, np.random.default_rng(31), trials=19)
        out.append((rec.gyro_rad_s, rec.accel_m_s2))
    for a, b in zip(*out):
        np.testing.assert_array_equal(a, b)


def test_trial_ids_bad_input():
    traj = _static(10, 10.0)
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-3))
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="distinct integers"):
        simulate.simulate_imu(traj, model, rng, trial_ids=[1, 1])
    with pytest.raises(ValueError, match="distinct integers"):
        simulate.simulate_imu(traj, model, rng, trial_ids=[-1])
    with pytest.raises(ValueError, match="non-empty 1-D sequence of integers"):
        simulate.simulate_imu(traj, model, rng, trial_ids=[0.5])
    with pytest.raises(ValueError, match=r"trials \(3\) must equal len\(trial_ids\)"):
        simulate.simulate_imu(traj, model, rng, trials=3, trial_ids=[0, 1])
    with pytest.raises(ValueError, match="trial_ids needs a per-trial truth"):
        simulate.apply_sensor_errors(model.gyro, np.zeros((10, 3)), traj.time_s, rng, trial_ids=[0])


def _reference_truth(traj, gravity=simulate.GRAVITY_W_M_S2):
    """The numpy expressions the fused body-rate and specific-force kernels replace."""
    q = traj.q_wb
    dq = rotations.quat_multiply(rotations.quat_conjugate(q[:-1]), q[1:])
    omega = rotations.rotvec_from_quat(rotations.quat_normalize(dq)) / np.diff(traj.time_s)[:, None]
    rates = np.concatenate([omega, omega[-1:]], axis=0)
    c_wb = rotations.quat_to_matrix(q)
    force = np.einsum("nji,nj->ni", c_wb, traj.accel_w_m_s2 - np.asarray(gravity, dtype=float))
    return rates, force


@pytest.mark.parametrize("with_accel", [False, True])
def test_fused_truth_kernels_are_bit_identical(turntable, with_accel):
    assert len(turntable) >= rotations._KERNEL_MIN_ROWS   # the compiled path
    rng = np.random.default_rng(5)
    traj = Trajectory(turntable.time_s, turntable.q_wb,
                      rng.normal(size=(len(turntable), 3)) if with_accel else None)
    rates, force = _reference_truth(traj)
    assert simulate.body_rates(traj).tobytes() == rates.tobytes()
    assert simulate.specific_force(traj).tobytes() == force.tobytes()
    g = (0.1, -0.2, -9.7)
    assert simulate.specific_force(traj, g).tobytes() == _reference_truth(traj, g)[1].tobytes()


def test_trajectory_continuity_and_no_alias_of_caller_quaternions(turntable):
    q = turntable.q_wb.copy()
    q[1::2] *= -1.0                                            # sign flips every other sample
    traj = Trajectory(turntable.time_s, q)
    assert np.array_equal(traj.q_wb, rotations.make_continuous(q, axis=0))
    assert traj.q_wb is not q and not np.shares_memory(traj.q_wb, q)
    assert q[1, 0] < 0                                         # the caller's array is untouched


def test_truth_outputs_memoised_per_trajectory(turntable):
    import pickle

    model = ImuErrorModel(q_mount=tuple(rotations.quat_from_euler_zxy(0.01, 0.02, -0.03)))
    first = simulate.simulate_imu(turntable, model)
    rates, force = turntable._truth["rates"], turntable._truth["force"]
    again = simulate.simulate_imu(turntable, model)
    assert turntable._truth["rates"] is rates and turntable._truth["force"] is force   # reused
    assert np.array_equal(first.gyro_rad_s, again.gyro_rad_s) and np.array_equal(first.accel_m_s2, again.accel_m_s2)
    assert not rates.flags.writeable
    other = simulate.simulate_imu(turntable, model, gravity_w_m_s2=(0.0, 0.0, -9.7))
    assert not np.array_equal(other.accel_m_s2, first.accel_m_s2)
    assert np.array_equal(simulate.simulate_imu(turntable, model).accel_m_s2, first.accel_m_s2)
    clone = pickle.loads(pickle.dumps(turntable))
    assert clone._truth == {} and np.array_equal(simulate.simulate_imu(clone, model).gyro_rad_s, first.gyro_rad_s)
    with pytest.raises(ValueError, match="gravity_w_m_s2 must have last dimension 3"):
        simulate.simulate_imu(turntable, model, gravity_w_m_s2=(0.0, -9.8))


def test_warmup_decay_reused_only_for_equal_time_samples():
    t = np.arange(3000) * 1e-3
    first = simulate._warmup_decay(t, 300.0, 90.0)
    assert first.tobytes() == np.exp(-(t + 300.0) / 90.0).tobytes() and not first.flags.writeable
    assert simulate._warmup_decay(t.copy(), 300.0, 90.0) is first            # equal samples: reused
    assert simulate._warmup_decay(t, 300.0, 60.0) is not first               # another time constant
    shifted = t + 1e-3
    assert simulate._warmup_decay(shifted, 300.0, 90.0).tobytes() == np.exp(-(shifted + 300.0) / 90.0).tobytes()
    errs = SensorErrors(warmup_bias=(1e-3, 0.0, -1e-3), warmup_tau_s=90.0)
    a = simulate.apply_sensor_errors(errs, np.zeros((3000, 3)), t, time_since_power_on_s=300.0)
    b = simulate.apply_sensor_errors(errs, np.zeros((3000, 3)), t, time_since_power_on_s=300.0, engine="numpy")
    assert a.tobytes() == b.tobytes()


def test_stream_fill_writes_simulate_imus_numbers_into_given_arrays():
    traj = _static(501, 100.0)
    model = ImuErrorModel(gyro=_EVERY_SOURCE, accel=_EVERY_SOURCE, time_since_power_on_s=1.0)
    rec = simulate.simulate_imu(traj, model, rng=np.random.default_rng(4), trials=3)
    g, a = np.empty((3, 501, 3)), np.empty((3, 501, 3))
    stream = simulate.ImuStream(traj, model, rng=np.random.default_rng(4), trials=3)
    stream.fill(g, a)
    assert np.array_equal(g, rec.gyro_rad_s) and np.array_equal(a, rec.accel_m_s2)
    with pytest.raises(ValueError, match="once per ImuStream"):
        stream.fill(g, a)
    with pytest.raises(ValueError, match="accel_out must be a writeable C-contiguous float64"):
        simulate.ImuStream(traj, model, rng=np.random.default_rng(4), trials=3).fill(g, a[:, ::2])


def test_tilted_trajectory_is_the_expressions_bit_for_bit():
    rng = np.random.default_rng(7)
    n = 6000
    t = np.arange(n) / 1000.0
    angles = np.cumsum(rng.normal(size=(n, 3)) * 2e-3, axis=0)
    angles[1000:3000] = angles[1000]                         # a rest: repeated axis rows reuse their rotation
    q_base = rotations.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2])
    axis = np.cross([0.0, 0.0, 1.0], -rotations.quat_to_matrix(q_base)[:, 2, :])
    for gain in (3e-3, -0.7):
        fused = simulate.tilted_trajectory(t, q_base, axis, gain)
        ref = Trajectory(t, rotations.hamilton(q_base, rotations.quat_from_rotvec(gain * axis)))
        assert np.array_equal(fused.q_wb, ref.q_wb)
        assert np.array_equal(simulate._truth_outputs(fused, simulate.GRAVITY_W_M_S2)[0], simulate.body_rates(ref))
        assert np.array_equal(simulate._truth_outputs(fused, simulate.GRAVITY_W_M_S2)[1],
                              simulate.specific_force(ref))
        assert not fused.q_wb.flags.writeable and fused.dt_s == ref.dt_s
    assert simulate.tilted_trajectory(t, q_base, axis, 0.0).q_wb.tolist() == Trajectory(t, q_base).q_wb.tolist()


def test_tilted_trajectory_checks_its_inputs():
    t = np.arange(10) * 0.01
    q = np.tile([1.0, 0.0, 0.0, 0.0], (10, 1))
    with pytest.raises(ValueError, match="must match time_s"):
        simulate.tilted_trajectory(t, q, np.zeros((9, 3)), 0.1)
    with pytest.raises(ValueError, match="gain must be finite"):
        simulate.tilted_trajectory(t, q, np.zeros((10, 3)), np.nan)
    with pytest.raises(ValueError, match="q_base"):
        simulate.tilted_trajectory(t, 2.0 * q, np.zeros((10, 3)), 0.1)


def test_tilted_trajectories_check_once_and_give_tilted_trajectory_bit_for_bit():
    rng = np.random.default_rng(4)
    n = 4000
    t = np.arange(n) * 1e-3
    q_base = rotations.quat_from_euler_zxy(*(np.cumsum(rng.normal(0, 1e-3, (3, n)), axis=1)))
    axis = np.repeat(rng.normal(0, 1, (n // 100, 3)), 100, axis=0)
    family = simulate.TiltedTrajectories(t, q_base, axis)
    assert not family.time_s.flags.writeable and family.time_s is not t
    for gain in (2e-3, -1e-3, 0.0, 2e-3):
        a, b = family(gain), simulate.tilted_trajectory(t, q_base, axis, gain)
        assert np.array_equal(a.q_wb, b.q_wb)
        assert np.array_equal(a._truth.get("rates", 0), b._truth.get("rates", 0))
        assert np.array_equal(a._truth.get("force", 0), b._truth.get("force", 0))
    with pytest.raises(ValueError, match="gain must be finite, got inf"):
        family(np.inf)
    with pytest.raises(ValueError, match="time_s must be uniformly sampled|uniform"):
        simulate.TiltedTrajectories(np.r_[t[:-1], t[-1] + 0.5], q_base, axis)
    with pytest.raises(ValueError, match="gravity_w_m_s2"):
        simulate.TiltedTrajectories(t, q_base, axis, gravity_w_m_s2=(0.0, -9.8))


def _shared_models():
    """Error models that share their noise scales and differ in everything else (sources on/off per model)."""
    from dataclasses import replace

    gyro = _EVERY_SOURCE
    accel = SensorErrors(noise_density=1e-3, bias_random_walk=1e-4, bias_instability=1e-4, quantization=1e-4)
    return [ImuErrorModel(gyro=gyro, accel=accel, time_since_power_on_s=1.0),
            ImuErrorModel(gyro=replace(gyro, bias_sigma=0.0, warmup_bias=0.0, vibration_amplitude=0.0,
                                       quantization=0.0, scale_factor=0.0), accel=replace(accel, bias=0.2),
                          q_mount=(np.cos(0.1), 0.0, np.sin(0.1), 0.0)),
            ImuErrorModel(gyro=replace(gyro, bias_sigma=3e-4, bias=0.0), accel=replace(accel, quantization=0.0,
                                                                                    bias_sigma=0.01))]


def _separate_and_shared(trajs, models, trials, block=256, **kw):
    n = len(trajs[0])
    fresh = lambda: [simulate.ImuStream(tr, m, np.random.default_rng(5), trials=trials, block_samples=block, **kw)  # noqa: E731
                     for tr, m in zip(trajs, models)]
    separate, shared = [], [(np.empty((trials, n, 3)), np.empty((trials, n, 3))) for _ in models]
    for stream in fresh():
        out = (np.empty((trials, n, 3)), np.empty((trials, n, 3)))
        stream.fill(*out)
        separate.append(out)
    simulate.fill_streams(fresh(), shared)
    return separate, shared


@pytest.mark.parametrize("min_work", [0, 10 ** 12])     # always / never the trial-parallel kernel
@pytest.mark.parametrize("block", [8, 256])
def test_fill_streams_equals_separate_fills_bit_for_bit(monkeypatch, turntable, min_work, block):
    """Streams on one key with equal noise scales: the shared fill (noise drawn once) writes each stream's
    own numbers: every source on in one model, several off in another, other truth, mount and biases; trials
    across more than 8 groups of the parallel kernel, an odd record length, kernel blocks of 8 and 256."""
    monkeypatch.setattr(simulate, "PARALLEL_MIN_WORK", min_work)
    n = len(turntable) - 1                      # odd
    t = turntable.time_s[:n]
    other = Trajectory(t, rotations.hamilton(turntable.q_wb[:n], np.array([np.cos(0.2), np.sin(0.2), 0.0, 0.0])))
    trajs = [Trajectory(t, turntable.q_wb[:n]), other, other]
    separate, shared = _separate_and_shared(trajs, _shared_models(), 67, block)
    for (g, a), (g_s, a_s) in zip(separate, shared):
        np.testing.assert_array_equal(g, g_s)
        np.testing.assert_array_equal(a, a_s)
    assert not np.array_equal(separate[0][0], separate[2][0])   # the models do differ


def test_fill_streams_numpy_engine_and_one_stream():
    traj = _static(301, 100.0)
    for models in (_shared_models(), _shared_models()[:1]):
        for engine in ("numba", "numpy"):
            separate, shared = _separate_and_shared([traj] * len(models), models, 3, engine=engine)
            for x, y in zip(separate, shared):
                np.testing.assert_array_equal(x[0], y[0])
                np.testing.assert_array_equal(x[1], y[1])


def test_fill_streams_refuses_streams_without_shared_noise():
    from dataclasses import replace

    traj = _static(200, 100.0)
    m0, m1 = _shared_models()[:2]
    out = lambda trials=4, n=200: (np.empty((trials, n, 3)), np.empty((trials, n, 3)))  # noqa: E731
    stream = lambda m=m0, rng=1, trajectory=traj, **kw: simulate.ImuStream(  # noqa: E731
        trajectory, m, np.random.default_rng(rng), **({"trials": 4} | kw))
    cases = [
        ([stream(), stream(m1, rng=2)], "another generator key"),
        ([stream(), stream(m1, trial_ids=[0, 1, 2, 5])], "other trial ids"),
        ([stream(), stream(m1, trajectory=_static(200, 50.0))], "another time base"),
        ([stream(), stream(m1, block_samples=64)], "another engine or block size"),
        ([stream(), stream(replace(m1, accel=replace(m1.accel, noise_density=2e-3)))],
         r"accel\.noise_density = 0\.002, not 0\.001"),
        ([stream(), stream(replace(m1, gyro=replace(m1.gyro, bias_instability_tau_s=5.0)))],
         r"gyro\.bias_instability_tau_s"),
    ]
    for streams, match in cases:
        with pytest.raises(ValueError, match=match):
            simulate.fill_streams(streams, [out(), out()])
    with pytest.raises(ValueError, match="non-empty and of equal length"):
        simulate.fill_streams([stream()], [out(), out()])
    with pytest.raises(TypeError, match=r"streams\[1\] must be an ImuStream"):
        simulate.fill_streams([stream(), "x"], [out(), out()])
    with pytest.raises(ValueError, match=r"outputs\[0\] must be a pair"):
        simulate.fill_streams([stream()], [out()[0]])
    with pytest.raises(ValueError, match=r"streams\[1\]: accel_out must be a writeable"):
        simulate.fill_streams([stream(), stream(m1)], [out(), (out()[0], np.empty((4, 199, 3)))])
    used = stream()
    used.fill(*out())
    with pytest.raises(ValueError, match=r"streams\[0\]: fill\(\) and chunks\(\) can run once"):
        simulate.fill_streams([used, stream(m1)], [out(), out()])


@pytest.mark.parametrize("shape", [(2048, 3), (2049, 3), (4097, 3), (3, 2731, 3), (224050, 3)])
def test_rows_at_equals_matmul_bit_for_bit(shape):
    """The compiled thin product is ``a @ m`` exactly (row counts on and off any blocking of the BLAS call),
    including non-finite rows; a small, non-float64 or non-contiguous input takes the matmul itself."""
    from mtcal.core.simulate import _rows_at

    rng = np.random.default_rng(7)
    a = rng.standard_normal(shape) * 10.0 ** rng.uniform(-6, 6, shape)
    a.reshape(-1, 3)[5] = [np.nan, np.inf, -np.inf]
    m = rng.standard_normal((3, 3))
    for mat in (m, m.T):                              # the transposed (non-contiguous) matrix the callers pass
        np.testing.assert_array_equal(_rows_at(a, mat), a @ mat)
        assert _rows_at(a, mat).tobytes() == (a @ mat).tobytes()
    small = a.reshape(-1, 3)[:10]
    assert _rows_at(small, m).tobytes() == (small @ m).tobytes()
    assert _rows_at(a.astype(np.float32), m).dtype == np.float64


def _tilting_base(n: int = 2000):
    t = np.arange(n) * 1e-3
    roll = np.linspace(0.0, np.pi / 2, n)
    q = rotations.quat_from_euler_zxy(np.zeros(n), np.zeros(n), roll)
    return t, q, simulate.gravity_lateral_axis(q)


def test_record_source_fills_each_block_as_its_own_stream_with_its_changes():
    """A block's records are those of its own ImuStream on its tilted truth, then its bias step and load tilt,
    whichever blocks are filled with it and in whatever groups."""
    t, q, axis = _tilting_base()
    noisy = ImuErrorModel(gyro=SensorErrors(noise_density=1e-3), accel=SensorErrors(noise_density=1e-3),
                          q_mount=rotations.quat_from_euler_zxy(0.01, 0.02, -0.01))
    step, tilt = np.full((2, 1, 3), 0.25), np.array([[1e-3, -2e-3, 0.0], [3e-4, 0.0, 0.0]])
    pieces = [simulate.RecordPiece(2, noisy, np.random.default_rng(1), 2e-3, step, tilt),
              simulate.RecordPiece(3, noisy, np.random.default_rng(2)),
              simulate.RecordPiece(2, noisy, np.random.default_rng(1), 2e-3)]
    fresh = lambda: simulate.RecordSource(t, q, [simulate.RecordPiece(p.trials, p.model, np.random.default_rng(s),  # noqa: E731
                                                                      p.tilt_gain, p.accel_step_m_s2, p.load_tilt_rad)
                                                 for p, s in zip(pieces, (1, 2, 1))], 1e-3, tilt_axis=axis, step_start=700)
    gyro, accel = fresh().fill([0, 1, 2], [[0, 2], [1]])
    assert gyro.shape == (7, t.size, 3)
    for i, (a, b), seed in ((0, (0, 2), 1), (1, (2, 5), 2), (2, (5, 7), 1)):
        traj = simulate.tilted_trajectory(t, q, axis, pieces[i].tilt_gain) if pieces[i].tilt_gain else Trajectory(t, q)
        g, acc = np.empty((b - a, t.size, 3)), np.empty((b - a, t.size, 3))
        simulate.ImuStream(traj, noisy, np.random.default_rng(seed), trials=b - a).fill(g, acc)
        if pieces[i].accel_step_m_s2 is not None:
            acc[:, 700:] += step
            simulate.load_tilt_outputs(g, acc, traj.q_wb, 1e-3, noisy.q_mount, tilt)
        assert np.array_equal(gyro[a:b], g) and np.array_equal(accel[a:b], acc)
    alone = fresh()
    g2, a2 = alone.fill([2], [[0]])
    assert np.array_equal(g2, gyro[5:7]) and np.array_equal(a2, accel[5:7])


def test_record_source_shares_a_gains_truth_and_drops_it_after_its_last_block(monkeypatch):
    t, q, axis = _tilting_base()
    made = []
    tilted = simulate.TiltedTrajectories.__call__
    monkeypatch.setattr(simulate.TiltedTrajectories, "__call__", lambda self, k: made.append(k) or tilted(self, k))
    src = simulate.RecordSource(t, q, [simulate.RecordPiece(1, ImuErrorModel(), None, k) for k in (1e-3, 1e-3, 2e-3)],
                                1e-3, tilt_axis=axis)
    first = src._trajectory(src.pieces[0])
    assert src._trajectory(src.pieces[1]) is first and 1e-3 not in src._memo
    src.fill([2], [[0]])
    assert made == [1e-3, 2e-3] and src._memo == {}


def test_record_source_bad_input():
    t, q, _ = _tilting_base(100)
    with pytest.raises(TypeError, match="pieces must be a non-empty sequence of RecordPiece"):
        simulate.RecordSource(t, q, [], 1e-3)
    with pytest.raises(ValueError, match="tilt_axis is needed"):
        simulate.RecordSource(t, q, [simulate.RecordPiece(1, ImuErrorModel(), None, 1e-3)], 1e-3)
    with pytest.raises(ValueError, match="step_start is needed"):
        simulate.RecordSource(t, q, [simulate.RecordPiece(1, ImuErrorModel(), None, 0.0, np.zeros((1, 1, 3)))], 1e-3)
    with pytest.raises(ValueError, match="time_s and q_base are needed"):
        simulate.RecordSource(None, None, [simulate.RecordPiece(1, ImuErrorModel(), None)], 1e-3)
    with pytest.raises(ValueError, match="a piece's trials must be an integer >= 1"):
        simulate.RecordSource(t, q, [simulate.RecordPiece(0, ImuErrorModel(), None)], 1e-3)
    with pytest.raises(TypeError, match="a piece's trajectory must be a Trajectory"):
        simulate.RecordSource(None, None, [simulate.RecordPiece(1, ImuErrorModel(), None, trajectory=q)], 1e-3)
    with pytest.raises(ValueError, match="dt_s"):
        simulate.RecordSource(t, q, [simulate.RecordPiece(1, ImuErrorModel(), None)], -1e-3)


def test_record_source_holds_a_shorter_block_at_its_last_sample_and_adds_its_disturbance():
    t, q, _ = _tilting_base(300)
    short = Trajectory(t[:200], q[:200])
    noisy = ImuErrorModel(accel=SensorErrors(noise_density=1e-3))
    shake = np.sin(np.arange(200.0))[None, :, None] * np.ones((2, 1, 3))
    src = simulate.RecordSource(None, None, [simulate.RecordPiece(2, noisy, np.random.default_rng(3), trajectory=short,
                                                                  accel_offset_m_s2=shake),
                                             simulate.RecordPiece(1, noisy, np.random.default_rng(4),
                                                                  trajectory=Trajectory(t, q))], 1e-3)
    gyro, accel = src.fill([0, 1], [[0], [1]])
    g, a = np.empty((2, 200, 3)), np.empty((2, 200, 3))
    simulate.ImuStream(short, noisy, np.random.default_rng(3), trials=2).fill(g, a)
    a += shake
    assert gyro.shape == (3, 300, 3) and np.array_equal(accel[:2, :200], a) and np.array_equal(gyro[:2, :200], g)
    assert np.array_equal(accel[:2, 200:], np.repeat(a[:, -1:], 100, axis=1))
