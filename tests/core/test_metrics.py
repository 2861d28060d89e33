import numpy as np
import pytest

from mtcal.core import metrics
from mtcal.core.metrics import bootstrap_medians


def test_angle_difference_wraps():
    d = metrics.angle_difference(np.radians([179.0, -179.0]), np.radians([-179.0, 179.0]))
    np.testing.assert_allclose(np.degrees(d), [-2.0, 2.0], atol=1e-12)


def test_rmse_and_maxae_with_mask():
    err = np.array([[1.0, -1.0, 3.0, 0.0], [2.0, 2.0, 2.0, 2.0]])
    np.testing.assert_allclose(metrics.rmse(err), [np.sqrt(11 / 4), 2.0])
    np.testing.assert_allclose(metrics.max_abs_error(err), [3.0, 2.0])
    mask = np.array([True, True, False, False])
    np.testing.assert_allclose(metrics.rmse(err, mask=mask), [1.0, 2.0])
    np.testing.assert_allclose(metrics.max_abs_error(err, mask=mask), [1.0, 2.0])


def test_split_static_moving():
    err = np.array([0.1, -0.1, 5.0, -5.0])
    out = metrics.split_static_moving(err, np.array([True, True, False, False]))
    assert out["static_rmse"] == pytest.approx(0.1)
    assert out["moving_max"] == pytest.approx(5.0)


def test_allan_of_white_noise_is_n_over_sqrt_tau(rng):
    fs, n = 100.0, 0.01
    x = n * np.sqrt(fs) * rng.standard_normal((4, 200_000))
    taus, adev = metrics.allan_deviation(x, 1.0 / fs, taus_s=[0.1, 1.0, 10.0])
    np.testing.assert_allclose(adev, n / np.sqrt(taus), rtol=0.05)


def test_percentile_band(rng):
    band = metrics.percentile_band(rng.standard_normal(100_000))
    assert band["median"] == pytest.approx(0.0, abs=0.02)
    assert band["high"] == pytest.approx(1.96, abs=0.05)


def test_bad_input():
    with pytest.raises(TypeError, match="mask must be boolean"):
        metrics.rmse([1.0, 2.0], mask=[1, 0])
    with pytest.raises(ValueError, match="at least one sample"):
        metrics.rmse([1.0, 2.0], mask=np.array([False, False]))
    with pytest.raises(ValueError, match="must broadcast"):
        metrics.rmse([1.0, 2.0], mask=np.array([True, False, True]))
    with pytest.raises(ValueError, match="finite"):
        metrics.rmse([1.0, np.nan])
    with pytest.raises(ValueError, match="at least 9 samples"):
        metrics.allan_deviation(np.ones(5), 0.1)
    with pytest.raises(ValueError, match="dt_s must be > 0"):
        metrics.allan_deviation(np.ones(100), 0.0)
    with pytest.raises(ValueError, match=r"dt_s must be the sample interval in s .*a sample rate in Hz"):
        metrics.allan_deviation(np.ones(100), 10.0)
    with pytest.raises(ValueError, match="level must be"):
        metrics.percentile_band([1.0, 2.0], level=95)


# --- bootstrap_medians (bands of statistics built from Monte Carlo medians)

def test_shape_and_constant_samples():
    rng = np.random.default_rng(0)
    boot = bootstrap_medians([np.full(5, 2.0), np.full(7, 3.0)], rng, n_boot=50)
    assert boot.shape == (50, 2)
    np.testing.assert_array_equal(boot[:, 0], 2.0)
    np.testing.assert_array_equal(boot[:, 1], 3.0)


def test_medians_are_resampled_values_and_spread_shrinks_with_n():
    rng = np.random.default_rng(1)
    small, large = rng.standard_normal(51), rng.standard_normal(2001)
    boot = bootstrap_medians([small, large], rng, n_boot=400)
    assert np.all(np.isin(boot[:, 0], small))  # odd n: the median is one of the samples
    # standard error of the median ≈ 1.2533 / sqrt(n) for a unit normal
    assert np.std(boot[:, 0]) == pytest.approx(1.2533 / np.sqrt(51), rel=0.35)
    assert np.std(boot[:, 1]) < 0.3 * np.std(boot[:, 0])


def test_bad_input_raises():
    rng = np.random.default_rng(2)
    with pytest.raises(TypeError, match="rng"):
        bootstrap_medians([np.ones(3)], 1, n_boot=10)
    with pytest.raises(ValueError, match="samples"):
        bootstrap_medians([np.ones(1)], rng, n_boot=10)
    with pytest.raises(ValueError, match="samples"):
        bootstrap_medians([], rng, n_boot=10)
    with pytest.raises(ValueError, match=r"samples\[0\]"):
        bootstrap_medians([np.array([1.0, np.nan])], rng, n_boot=10)
    with pytest.raises(ValueError, match="n_boot"):
        bootstrap_medians([np.ones(3)], rng, n_boot=0)


def test_angle_difference_compiled_loop_equals_numpy_remainder_bit_for_bit(monkeypatch):
    rng = np.random.default_rng(5)
    e = rng.uniform(-7, 7, (3, 4000, 3))
    t = rng.uniform(-7, 7, (4000, 3))
    e[0, :100] = t[:100]                      # zero difference: (0 + π) mod 2π − π
    e[0, 100:200] = t[100:200] + np.pi        # exactly ±π and 2π apart
    e[0, 200:300] = t[200:300] - np.pi
    e[0, 300:400] = t[300:400] + 2 * np.pi
    e[1, :1000] = np.pi
    t[:1000] = -0.0
    got = {k: metrics.angle_difference(a, b) for k, (a, b) in
           {"3d": (e, t), "strided": (e[:, ::3], t[::3]), "1d": (e[0, :, 0], t[:, 1])}.items()}
    monkeypatch.setattr(metrics, "_KERNEL_MIN_SIZE", 10 ** 15)
    for k, (a, b) in {"3d": (e, t), "strided": (e[:, ::3], t[::3]), "1d": (e[0, :, 0], t[:, 1])}.items():
        ref = metrics.angle_difference(a, b)
        assert np.array_equal(got[k], ref) and np.array_equal(np.signbit(got[k]), np.signbit(ref)), k


def test_angle_difference_rejects_shapes_that_do_not_broadcast():
    with pytest.raises(ValueError, match="must broadcast"):
        metrics.angle_difference(np.zeros((9000, 3)), np.zeros((9000, 2)))


def test_band_or_range_is_a_95_percent_band_only_from_1000_draws():
    from mtcal.core.metrics import MIN_BAND_DRAWS, band_label, band_or_range, percentile_band

    x = np.random.default_rng(3).normal(size=(MIN_BAND_DRAWS, 2))
    many = band_or_range(x)
    ref = percentile_band(x)
    assert many["kind"] == "95 % band" and many["n"] == MIN_BAND_DRAWS
    assert all(np.array_equal(many[k], ref[k]) for k in ("median", "low", "high"))
    assert many["label"] == "95 % band of 1000 trials"
    few = band_or_range(x[:999], what="repetitions")          # one draw short: the min-max range
    assert few["kind"] == "range" and few["n"] == 999
    assert np.array_equal(few["low"], x[:999].min(axis=0)) and np.array_equal(few["high"], x[:999].max(axis=0))
    assert few["label"] == "range of 999 repetitions (fewer than 1000: no 95 % band)"
    per_row = band_or_range(x[:5].T, axis=1)                  # the draw axis is the caller's
    assert per_row["n"] == 5 and per_row["low"].shape == (2,)
    kept = band_or_range([2.0, np.nan, 1.0, np.inf], finite_only=True)
    assert kept["n"] == 2 and (kept["low"], kept["high"]) == (1.0, 2.0)
    assert band_label(1) == "range of 1 trials (fewer than 1000: no 95 % band)"


def test_band_or_range_errors():
    from mtcal.core.metrics import band_label, band_or_range

    with pytest.raises(ValueError, match="samples"):
        band_or_range([1.0, np.nan])                           # a non-finite draw is an error unless dropped
    with pytest.raises(ValueError, match="at least one finite"):
        band_or_range([np.nan], finite_only=True)
    with pytest.raises(ValueError, match="dimension"):
        band_or_range(1.0)
    with pytest.raises(ValueError, match="n"):
        band_label(0)


def test_percentile_band_records_its_draw_count():
    x = np.random.default_rng(5).normal(size=(7, 3))
    assert metrics.percentile_band(x)["n"] == 7                  # draws along the (default) axis 0
    assert metrics.percentile_band(x, axis=1)["n"] == 3
    with pytest.raises(ValueError, match="samples must have at least one dimension"):
        metrics.percentile_band(1.0)


# --- orientation_errors (BROAD's earth-frame error definitions) ------------------------------

def _scalar_first(rot):
    return np.roll(rot.as_quat(), 1, axis=-1)


def test_orientation_errors_total_equals_scipy_relative_angle():
    from scipy.spatial.transform import Rotation

    from mtcal.core.metrics import orientation_errors

    a, b = Rotation.random(500, random_state=1), Rotation.random(500, random_state=2)
    e = orientation_errors(_scalar_first(a), -_scalar_first(b))     # sign of q_ref does not matter
    np.testing.assert_allclose(e.total_rad, (a * b.inv()).magnitude(), atol=1e-12)


def test_orientation_errors_split_heading_then_tilt():
    """An earth-frame error = heading h about z after a tilt t about a horizontal axis."""
    from scipy.spatial.transform import Rotation

    from mtcal.core.metrics import orientation_errors

    rng = np.random.default_rng(3)
    h = rng.uniform(-3, 3, 200)
    t = rng.uniform(0, 3, 200)
    phi = rng.uniform(-np.pi, np.pi, 200)
    axis = np.stack([np.cos(phi), np.sin(phi), np.zeros(200)], axis=1)
    ref = Rotation.random(200, random_state=4)
    err = Rotation.from_rotvec(h[:, None] * [0, 0, 1]) * Rotation.from_rotvec(t[:, None] * axis)
    e = orientation_errors(_scalar_first(err * ref), _scalar_first(ref))
    np.testing.assert_allclose(e.heading_rad, np.abs(h), atol=1e-9)
    np.testing.assert_allclose(e.inclination_rad, t, atol=1e-9)


def test_orientation_errors_nan_reference_rows_skipped_by_rmse():
    from mtcal.core.metrics import orientation_errors, rmse_over_phase

    half = np.radians(2.0) / 2
    est = np.tile([np.cos(half), np.sin(half), 0, 0], (4, 1))
    ref = np.tile([1.0, 0, 0, 0], (4, 1))
    ref[1] = np.nan
    e = orientation_errors(est, ref)
    assert np.isnan(e.inclination_rad[1])
    assert np.degrees(rmse_over_phase(e.inclination_rad)) == pytest.approx(2.0)
    assert np.degrees(rmse_over_phase(e.inclination_rad, [1, 1, 0, 0])) == pytest.approx(2.0)
    with pytest.raises(ValueError, match="no finite error sample"):
        rmse_over_phase(e.inclination_rad, [0, 1, 0, 0])
    with pytest.raises(ValueError, match="shape of error"):
        rmse_over_phase(e.inclination_rad, [1, 1])
    with pytest.raises(ValueError, match="infinite"):
        rmse_over_phase([np.inf])
    with pytest.raises(ValueError, match="1-D"):
        rmse_over_phase(np.ones((2, 2)))


def test_orientation_errors_rejects_bad_shapes():
    from mtcal.core.metrics import orientation_errors

    with pytest.raises(ValueError, match="shape"):
        orientation_errors(np.ones((3, 3)), np.ones((3, 4)))
    with pytest.raises(ValueError, match="same length"):
        orientation_errors(np.ones((3, 4)), np.ones((2, 4)))
    with pytest.raises(ValueError, match="infinite"):
        orientation_errors(np.ones((1, 4)), np.array([[np.inf, 0, 0, 0]]))


def test_variance_parts_split_and_its_old_homes_reexport_it():
    from mtcal.studies.wang2023cja import predictive, verdicts

    assert predictive.variance_parts is metrics.variance_parts is verdicts.variance_parts
    rng = np.random.default_rng(2)
    y = np.repeat(rng.normal(0, 3.0, 3000), 3) + rng.normal(0, 1.0, 9000)
    p = metrics.variance_parts(y, 3)
    assert abs(p["parameter"] - 9.0) < 0.8 and abs(p["sampling"] - 1.0) < 0.05 and p["draws"] == 3000
    assert p["total"] == p["parameter"] + p["sampling"] and 0.85 < p["parameter_share"] < 0.95
    with pytest.raises(ValueError, match="per_draw must be >= 2"):
        metrics.variance_parts(y, 1)
    with pytest.raises(ValueError, match="samples must be 1-D"):
        metrics.variance_parts(y.reshape(-1, 3), 3)
    with pytest.raises(ValueError, match="at least 2 complete groups"):
        metrics.variance_parts(y[:5], 3)


@pytest.mark.parametrize("shape", [(5, 3), (4000, 3), (2, 3000, 3)])   # numpy path and the compiled path
def test_angle_difference_trusted_bit_identical(shape):
    rng = np.random.default_rng(35)
    e, t = rng.uniform(-7, 7, shape), rng.uniform(-7, 7, shape[-1:])
    assert np.array_equal(metrics.angle_difference_trusted(e, t), metrics.angle_difference(e, t))
    assert "angle_difference_trusted" not in metrics.__all__
    with pytest.raises(ValueError, match="must broadcast"):   # the public call keeps its check
        metrics.angle_difference(e, t[:2])


def _allan_numpy(x, dt_s):
    """The numpy expressions allan_deviation ran before its compiled pass (reference for bit-identity)."""
    x = np.array(x, dtype=np.float64, copy=True)
    fs = 1.0 / dt_s
    n = x.shape[-1]
    m = np.unique(np.round(np.logspace(0, np.log10(n / 3), 60)).astype(int))
    theta = np.concatenate([np.zeros(x.shape[:-1] + (1,)), np.cumsum(x, axis=-1)], axis=-1) / fs
    avar = np.array([np.mean((theta[..., 2 * mi:] - 2 * theta[..., mi:-mi] + theta[..., :-2 * mi]) ** 2)
                     / (2.0 * (mi / fs) ** 2) for mi in m])
    return m / fs, np.sqrt(avar)


@pytest.mark.parametrize("layout", ["1d", "2d", "2d_fortran", "3d", "moved_axis", "4d"])
def test_allan_deviation_compiled_pass_bit_identical(layout):
    rng = np.random.default_rng(3)
    x = {"1d": lambda: rng.normal(size=30000), "2d": lambda: rng.normal(size=(3, 12000)),
         "2d_fortran": lambda: np.asfortranarray(rng.normal(size=(3, 12000))),
         "3d": lambda: rng.normal(size=(2, 3, 9000)),
         "moved_axis": lambda: np.moveaxis(rng.normal(size=(2, 9000, 3)), -1, 1),   # records (trials, N, 3)
         "4d": lambda: rng.normal(size=(2, 2, 2, 3000))}[layout]()
    taus, adev = metrics.allan_deviation(x, 0.1)
    ref_taus, ref_adev = _allan_numpy(x, 0.1)
    assert taus.tobytes() == ref_taus.tobytes() and adev.tobytes() == ref_adev.tobytes()


def test_like_matches_numpy_layout():
    a = np.moveaxis(np.zeros((2, 50, 3)), -1, 1)[..., 4:]
    out = metrics._like(a, np.empty(a.size + 7))
    assert out.shape == a.shape and out.strides == np.empty_like(a).strides


def test_inclination_error_is_orientation_errors_field():
    rng = np.random.default_rng(9)
    est, ref = rng.normal(size=(500, 4)), rng.normal(size=(500, 4))
    ref[7] = np.nan
    got = metrics.inclination_error(est, ref)
    assert got.tobytes() == metrics.orientation_errors(est, ref).inclination_rad.tobytes()
    with pytest.raises(ValueError, match="q_est and q_ref must have shape"):
        metrics.inclination_error(np.ones((3, 3)), np.ones((3, 4)))
