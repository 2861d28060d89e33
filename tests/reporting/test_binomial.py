"""binomial: the Wilson score interval and the one coin-flip rule (bake-off rankings, wang2023cja claims)."""

import numpy as np
import pytest

from mtcal.reporting import binomial


def test_wilson_interval_known_values_and_errors():
    lo, hi = binomial.wilson_interval(8, 10)
    assert (lo, hi) == pytest.approx((0.4902, 0.9433), abs=1e-4)
    assert binomial.wilson_interval(0, 5)[0] == 0.0 and binomial.wilson_interval(5, 5)[1] == 1.0
    with pytest.raises(ValueError, match="need n >= 1"):
        binomial.wilson_interval(3, 2)
    with pytest.raises(TypeError, match="k and n must be int"):
        binomial.wilson_interval(1.5, 2)
    with pytest.raises(TypeError, match="k and n must be int, got bool, int"):
        binomial.wilson_interval(True, 2)
    with pytest.raises(ValueError, match="level must be in"):
        binomial.wilson_interval(1, 2, level=1.0)


def test_fidelity_scores_use_the_same_interval():
    from mtcal.reporting import fidelity

    assert fidelity.wilson_interval is binomial.wilson_interval


@pytest.mark.parametrize(("n", "first_above", "last_below"), [(12, 10, 2), (3, None, None), (1000, 531, 469)])
def test_coin_flip_boundaries(n, first_above, last_below):
    """The smallest win count resolved above ½ and the largest resolved below, found by scanning every count."""
    flips = [binomial.coin_flip(k, n) for k in range(n + 1)]
    above = [k for k, f in enumerate(flips) if f.resolved and f.low > 0.5]
    below = [k for k, f in enumerate(flips) if f.resolved and f.high < 0.5]
    assert (min(above, default=None), max(below, default=None)) == (first_above, last_below)
    # resolved exactly when ½ is outside the interval; the two sides never overlap
    assert all(f.resolved == (not f.low <= 0.5 <= f.high) for f in flips)
    assert set(above).isdisjoint(below)


def test_coin_flip_replaces_the_two_standard_error_rule():
    """At n = 1000 the former wang2023cja rule (|p − ½| > 2·√(0.25/n)) needed 532 holding trials; Wilson: 531."""
    assert binomial.coin_flip(531, 1000).resolved and abs(0.531 - 0.5) <= 2 * np.sqrt(0.25 / 1000)
    assert not binomial.coin_flip(530, 1000).resolved


def test_coin_flip_at_n_12_flips_between_9_and_10_wins():
    nine, ten = binomial.coin_flip(9, 12), binomial.coin_flip(10, 12)
    assert nine == (pytest.approx(0.4677, abs=1e-4), pytest.approx(0.9111, abs=1e-4), False,
                    "not resolved: wins 9 of 12 paired trials (Wilson 95 % 0.47–0.91 includes ½)")
    assert ten.resolved and ten.verdict == "resolved: wins 10 of 12 paired trials (Wilson 95 % 0.55–0.95)"
    assert binomial.coin_flip(2, 12).verdict == "resolved: wins 2 of 12 paired trials (Wilson 95 % 0.05–0.45 below ½)"
    assert not binomial.coin_flip(3, 12).resolved
    assert not binomial.coin_flip(3, 3).resolved           # 3 of 3: too few trials to tell from a coin flip


def test_coin_flip_words_and_numpy_counts():
    c = binomial.coin_flip(np.int64(503), 1000, counted="holds in", of="trials")
    assert c.verdict == "not resolved: holds in 503 of 1000 trials (Wilson 95 % 0.47–0.53 includes ½)"
    assert isinstance(c, binomial.CoinFlip) and not c.resolved


def test_coin_flip_errors():
    with pytest.raises(ValueError, match=r"need n >= 1 and 0 <= k <= n, got k=0, n=0"):
        binomial.coin_flip(0, 0)
    with pytest.raises(ValueError, match=r"need n >= 1 and 0 <= k <= n, got k=1, n=-2"):
        binomial.coin_flip(1, -2)
    with pytest.raises(ValueError, match=r"need n >= 1 and 0 <= k <= n, got k=13, n=12"):
        binomial.coin_flip(13, 12)
    with pytest.raises(ValueError, match=r"need n >= 1 and 0 <= k <= n, got k=-1, n=12"):
        binomial.coin_flip(-1, 12)
    with pytest.raises(TypeError, match="k and n must be int, got float, int"):
        binomial.coin_flip(0.58, 12)
    with pytest.raises(TypeError, match="k and n must be int, got int, float"):
        binomial.coin_flip(7, 12.0)
