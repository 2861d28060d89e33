import numpy as np
import pytest

from mtcal.core import metrics, montecarlo, profiles, rotations, simulate
from mtcal.core.simulate import ImuErrorModel, SensorErrors


class GyroIntegrator:
    """Minimal consumer: integrates the gyro and accumulates attitude-angle errors."""

    def __init__(self, q0, dt, trials):
        self.q = np.tile(q0, (trials, 1))
        self.dt = dt
        self.acc = montecarlo.ErrorAccumulator((trials,))

    def update(self, chunk):
        inc = rotations.quat_from_rotvec(chunk.gyro_rad_s * self.dt)
        err = np.empty(inc.shape[:2])
        for k in range(inc.shape[1]):
            err[:, k] = rotations.quat_angle_between(self.q, np.broadcast_to(chunk.q_ws_true[k], self.q.shape))
            self.q = rotations.hamilton(self.q, inc[:, k])
        self.acc.add(err)


@pytest.fixture
def stream_args():
    wp = np.radians([[0, 0, 0], [8, 0, 0], [0, 20, -30]])
    traj = profiles.trajectory_from_euler_zxy(profiles.step_schedule(wp, np.radians(20), 0.3, 200))
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-3, bias_sigma=1e-3))
    return traj, model


@pytest.mark.parametrize("chunk", [7, 64, 10_000])
def test_streaming_metrics_independent_of_chunk_size(stream_args, chunk):
    traj, model = stream_args
    results = []
    for size in (chunk, 50):
        stream = simulate.ImuStream(traj, model, np.random.default_rng(11), trials=5)
        consumer = GyroIntegrator(traj.q_wb[0], traj.dt_s, 5)
        montecarlo.run_streaming(stream, [consumer], size, progress=False)
        results.append((consumer.acc.rmse(), consumer.acc.max_abs()))
    np.testing.assert_allclose(results[0][0], results[1][0], rtol=1e-12)
    np.testing.assert_array_equal(results[0][1], results[1][1])


def test_accumulator_matches_batch_metrics(rng):
    err = rng.normal(size=(4, 100, 3))
    acc = montecarlo.ErrorAccumulator((4, 3))
    for part in np.array_split(err, 7, axis=1):
        acc.add(part)
    np.testing.assert_allclose(acc.rmse(), metrics.rmse(err, axis=1))
    np.testing.assert_allclose(acc.max_abs(), metrics.max_abs_error(err, axis=1))
    np.testing.assert_allclose(acc.mean(), err.mean(axis=1))
    mask = np.arange(100) < 30
    acc_m = montecarlo.ErrorAccumulator((4, 3))
    acc_m.add(err, mask=mask)
    np.testing.assert_allclose(acc_m.rmse(), metrics.rmse(err[:, :30], axis=1))


def test_accumulator_and_runner_errors(stream_args):
    acc = montecarlo.ErrorAccumulator((4,))
    with pytest.raises(ValueError, match="no samples"):
        acc.rmse()
    with pytest.raises(ValueError, match="error must have shape"):
        acc.add(np.zeros((3, 10)))
    with pytest.raises(ValueError, match="mask must be a boolean"):
        acc.add(np.zeros((4, 10)), mask=np.ones(10))
    with pytest.raises(TypeError, match="stream must be an ImuStream"):
        montecarlo.run_streaming([1, 2], [object()])
    traj, _ = stream_args
    with pytest.raises(TypeError, match="consumers must be"):
        montecarlo.run_streaming(simulate.ImuStream(traj), [object()])


def test_progress_switch(monkeypatch):
    monkeypatch.setenv("MTCAL_PROGRESS", "0")
    assert not montecarlo.progress_enabled()
    monkeypatch.setenv("MTCAL_PROGRESS", "1")
    assert montecarlo.progress_enabled()
