"""Tests for mtcal.scenarios004.bootstrap_medians (bands of statistics built from Monte Carlo medians)."""

import numpy as np
import pytest

from mtcal.scenarios004 import bootstrap_medians


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
