"""Tests of mtcal.methods.rotation_axis (wang2022sensors Eq 23, Algorithm A1)."""

import numpy as np
import pytest

from mtcal.core import rotations
from mtcal.methods.rotation_axis import (AxisEstimator, apply_sign_convention, axis_error_std, axis_from_means,
                        estimate_axis, gravity_change_norm)

G0 = np.array([0.0, 0.0, 9.80665])


def _means(v, angles_deg, g0=G0):
    return [rotations.axis_angle_matrix(np.radians(a), v).T @ g0 for a in angles_deg]


@pytest.mark.parametrize("v", [[0.1734, 0.9835, 0.0523], [0.9932, 0.1044, 0.0523], [0.8070, 0.5864, -0.0698]])
def test_noise_free_recovery(v):
    v = np.array(v) / np.linalg.norm(v)
    est = axis_from_means(*_means(v, [0, 50, 130]))
    np.testing.assert_allclose(est, apply_sign_convention(v), atol=1e-9)


def test_minus_v_gives_same_axis_and_sign_convention():
    v = np.array([-0.3, 0.9, 0.1]) / np.linalg.norm([-0.3, 0.9, 0.1])
    a = axis_from_means(*_means(v, [0, 40, 80]))
    b = axis_from_means(*_means(-v, [0, 40, 80]))
    np.testing.assert_allclose(a, b, atol=1e-12)
    assert a[0] >= 0
    np.testing.assert_allclose(apply_sign_convention(np.array([0.0, -1.0, 0.0])), [0, 1, 0])


def test_degenerate_geometry_raises():
    v = np.array([0.0, 1.0, 0.0])
    m = _means(v, [0, 0.1, 40])
    with pytest.raises(ValueError, match=r"only 0\.1000 deg apart"):
        axis_from_means(*m)
    vert = np.array([np.cos(np.radians(88)), 0.0, np.sin(np.radians(88))])
    with pytest.raises(ValueError, match="apart|vertical"):
        axis_from_means(*_means(vert, [0, 60, 120]))
    with pytest.raises(ValueError, match="nearly vertical"):
        axis_from_means(*_means(vert, [0, 60, 120]), min_separation_deg=0.01)


def test_fewer_than_three_rests_raises(rng):
    a = np.tile(G0, (600, 1)) + 0.001 * rng.normal(size=(600, 3))
    a[200:300] += [1.0, 0, 0]
    with pytest.raises(ValueError, match="found only 1 distinct rest"):
        estimate_axis(a, 0.01, min_rest_s=0.5)


def test_streaming_equals_batch(rng):
    v = np.array([0.1734, 0.9835, 0.0523]) / np.linalg.norm([0.1734, 0.9835, 0.0523])
    blocks, flags = [], []
    for ang in (0, 60, 60, 150, 20):  # the repeated 60 is one rest split by a dropout: merged
        blocks.append(np.tile(_means(v, [ang])[0], (120, 1)) + 0.003 * rng.normal(size=(120, 3)))
        flags.append(np.ones(120, bool))
        blocks.append(np.tile([3.0, 0, 9], (20, 1)))
        flags.append(np.zeros(20, bool))
    a, st = np.concatenate(blocks), np.concatenate(flags)
    res = estimate_axis(a, 0.01, is_static=st, min_rest_s=1.0)
    est = AxisEstimator(min_rest_samples=100)
    done = [est.push(a[k], st[k]) for k in range(len(a))]
    assert done[-1] and not done[0]
    np.testing.assert_allclose(est.v, res.v, atol=1e-14)
    assert [(s.start, s.stop) for s in res.rests] == est.rests
    assert np.degrees(np.arccos(res.v @ v)) < 0.2


def test_fig12_formula_and_error_scaling():
    g = gravity_change_norm(np.radians([0.0, 60.0]), np.radians(30.0), 9.8)
    assert g[1] / g[0] == pytest.approx(0.5)
    v = np.array([np.cos(0.3), 0.0, np.sin(0.3)])
    m = _means(v, [0, 30, 0])[:2] + [rotations.axis_angle_matrix(np.radians(30), v).T @ _means(v, [0])[0]]
    np.testing.assert_allclose(np.linalg.norm(m[1] - m[0]), gravity_change_norm(0.3, np.radians(30), 9.80665))
    s = axis_error_std(1e-3, np.radians([0.0, 60.0]), np.radians([0, 90, 180]))
    assert s[1] / s[0] == pytest.approx(2.0)


def test_axis_error_std_matches_monte_carlo(rng):
    gam = np.radians(20.0)
    v = np.array([np.cos(gam), 0.0, np.sin(gam)])
    m = np.array(_means(v, [0, 90, 180]))
    sig = 0.01
    noisy = m[None] + sig * rng.normal(size=(4000, 3, 3))
    est = axis_from_means(noisy[:, 0], noisy[:, 1], noisy[:, 2])
    err = np.arccos(np.clip(est @ v, -1, 1))
    pred = axis_error_std(sig, gam, np.radians([0, 90, 180]))
    assert np.sqrt(np.mean(err**2)) == pytest.approx(float(pred), rel=0.08)


# ---------------------------------------------------------------- plane fit over all distinct rests
from mtcal.methods.rotation_axis import distinct_positions, fit_axis_plane  # noqa: E402


@pytest.mark.parametrize("v", [[0.1734, 0.9835, 0.0523], [0.8070, 0.5864, -0.0698]])
def test_plane_fit_equals_eq23_for_three_and_uses_more(v, rng):
    v = np.array(v) / np.linalg.norm(v)
    m = np.array(_means(v, [0, 50, 130]))
    np.testing.assert_allclose(fit_axis_plane(m, 0.01).v, axis_from_means(*m), atol=1e-12)
    noisy = np.array(_means(v, [0, 30, 60, 90, 120, 150])) + rng.normal(0, 0.01, (6, 3))
    fit = fit_axis_plane(noisy, 0.01)
    err = np.degrees(np.arccos(min(1.0, abs(fit.v @ v))))
    assert err < 4 * np.degrees(fit.sigma_rad) and fit.rms_out_of_plane_m_s2 > 0


def test_plane_fit_uncertainty_grows_as_rests_approach():
    v = np.array([1.0, 0.0, 0.0])
    wide = fit_axis_plane(np.array(_means(v, [0, 60, 120])), 0.017).sigma_rad
    close = fit_axis_plane(np.array(_means(v, [0, 1.7, 3.4])), 0.017).sigma_rad
    assert close > 30 * wide and np.degrees(close) > 1.0
    # first-order formula of axis_error_std for the same geometry
    ref = axis_error_std(0.017, 0.0, np.radians([0, 60, 120]))
    assert wide == pytest.approx(float(ref), rel=1e-6)


def test_distinct_positions_merges_same_tilt():
    v = np.array([1.0, 0.0, 0.0])
    m = np.array(_means(v, [0, 1.0, 90, 0.5, 180]))
    pos, w, members = distinct_positions(m, np.array([100.0, 50, 100, 50, 100]), min_separation_deg=3.0)
    assert members == [[0, 1, 3], [2], [4]] and w.tolist() == [200, 100, 100]


def test_one_function_per_step_no_trusted_twins():
    """The methods trust their inputs (documented preconditions); the systems check at their edge."""
    from mtcal.methods import rotation_axis as ra

    assert not [n for n, f in vars(ra).items() if n.endswith("_trusted") and getattr(f, "__module__", "") == ra.__name__]
    assert "_sign_convention" not in vars(ra)   # the private twin of apply_sign_convention folded too
    for name in ("apply_sign_convention", "angle_between", "axis_elevation", "axis_from_means", "distinct_positions", "fit_axis_plane",
                 "gated_plane_fit", "rest_means", "axis_from_rests", "axes_from_rests", "gated_elevation",
                 "estimate_axis"):
        assert "Preconditions" in getattr(ra, name).__doc__, name


def test_compiled_masked_rest_means_equal_numpy_bit_for_bit(rng):
    """``a[t][mask[t]].mean(axis=0)`` per trial, for any layout; trials without a masked sample untouched."""
    from mtcal.methods import _axis_kernels

    for n, share in ((1, 1.0), (7, 0.5), (3000, 0.9), (500, 0.0)):
        a = rng.normal(size=(5, n, 3)) * 0.1 + [0.1, 9.8, 0.3]
        for arr in (a, np.asfortranarray(a)):
            m = rng.random((5, n)) < share
            out = np.full((5, 3), np.nan)
            _axis_kernels.masked_means(arr, m, out)
            for t in range(5):
                if m[t].any():
                    assert np.array_equal(out[t], arr[t][m[t]].mean(axis=0))
                else:
                    assert np.all(np.isnan(out[t]))
