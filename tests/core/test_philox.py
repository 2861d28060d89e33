"""Philox4x32-10 and its transforms: known answers, statistics, counter/key layout.

Statistical tolerances are 5 standard errors of the statistic for the stated sample size
(the draws are seeded, so a test either always passes or always fails; 5σ keeps a correct
generator far from the edge while a biased transform is caught).
"""

import numpy as np
import pytest
from scipy import special, stats

from mtcal.core import philox

# Random123 tests/kat_vectors, "philox4x32 10" lines: counter[4], key[2] -> output[4]
KAT = [
    ((0x00000000, 0x00000000, 0x00000000, 0x00000000), (0x00000000, 0x00000000),
     (0x6627E8D5, 0xE169C58D, 0xBC57AC4C, 0x9B00DBD8)),
    ((0xFFFFFFFF, 0xFFFFFFFF, 0xFFFFFFFF, 0xFFFFFFFF), (0xFFFFFFFF, 0xFFFFFFFF),
     (0x408F276D, 0x41C83B0E, 0xA20BC7C6, 0x6D5451FD)),
    ((0x243F6A88, 0x85A308D3, 0x13198A2E, 0x03707344), (0xA4093822, 0x299F31D0),
     (0xD16CFE09, 0x94FDCCEB, 0x5001E420, 0x24126EA1)),
]
N_STAT = 10 ** 7


@pytest.fixture(scope="module")
def normals():
    return philox.standard_normals(N_STAT, key=(0x12345678, 0x9ABCDEF0), c1=7, c2=philox.stream_word(0, 1, 2))


@pytest.fixture(scope="module")
def uniforms():
    return philox.uniforms(N_STAT, key=(0x0BADF00D, 0x00C0FFEE), c1=3, c2=5)


@pytest.mark.parametrize("ctr,key,expected", KAT)
def test_known_answer_vectors(ctr, key, expected):
    assert philox.philox4x32_10(*ctr, *key) == expected


def test_ziggurat_tables_are_numpys():
    """Spot values of numpy's ziggurat_constants.h (256 layers)."""
    assert int(philox.KI[0]) == 0x000EF33D8025EF6A and int(philox.KI[1]) == 0
    assert philox.WI[0] == 8.68362706080130616677e-16
    assert philox.FI[0] == 1.0 and philox.FI[1] == 9.77101701267671596263e-01
    assert philox.KI.size == philox.WI.size == philox.FI.size == 256


def test_words_and_transforms_follow_the_stated_layout():
    """Lane 0 = x0 | x1 << 32, lane 1 = x2 | x3 << 32; uniform = top 53 bits · 2⁻⁵³."""
    x = philox.philox4x32_10(5, 7, 9, 0, 11, 13)
    u = philox.uniforms(2, key=(11, 13), c1=7, c2=9, c0_start=5)
    lane0, lane1 = x[0] | x[1] << 32, x[2] | x[3] << 32
    assert u.tolist() == [(lane0 >> 11) * 2.0 ** -53, (lane1 >> 11) * 2.0 ** -53]


def test_uniform_moments_and_range(uniforms):
    u = uniforms
    assert u.min() >= 0.0 and u.max() < 1.0
    se = np.sqrt(1 / 12 / N_STAT)
    assert abs(u.mean() - 0.5) < 5 * se
    assert abs(u.var() - 1 / 12) < 5 * np.sqrt(1 / 180 / N_STAT)   # var of (u − ½)² is 1/180
    assert np.unique(u[:100_000]).size == 100_000                  # 53-bit resolution: no repeats


def test_normal_moments(normals):
    z = normals
    n = z.size
    assert abs(z.mean()) < 5 / np.sqrt(n)
    assert abs(z.var() - 1.0) < 5 * np.sqrt(2 / n)
    assert abs(stats.skew(z)) < 5 * np.sqrt(6 / n)
    assert abs(stats.kurtosis(z)) < 5 * np.sqrt(24 / n)
    assert np.abs(z).max() > 4.5                                    # the tail branch is exercised


@pytest.mark.parametrize("name", ["uniforms", "normals"])
def test_lag_autocorrelation_1_to_10(name, request):
    x = request.getfixturevalue(name)
    x = x - x.mean()
    var = x @ x
    for lag in range(1, 11):
        r = (x[:-lag] @ x[lag:]) / var
        assert abs(r) < 5 / np.sqrt(x.size), f"lag {lag}: r = {r:.2e}"


@pytest.mark.parametrize("name", ["uniforms", "normals"])
def test_chi_square_buckets(name, request):
    """1000 equiprobable buckets (normals through Φ, so the tails are checked too)."""
    x = request.getfixturevalue(name)
    u = x if name == "uniforms" else special.ndtr(x)
    counts = np.bincount(np.minimum((u * 1000).astype(int), 999), minlength=1000)
    chi2 = ((counts - x.size / 1000) ** 2 / (x.size / 1000)).sum()
    p = stats.chi2.sf(chi2, 999)
    assert 1e-4 < p < 1 - 1e-4, f"chi2 = {chi2:.1f}, p = {p:.2g}"


def test_birthday_spacings():
    """Marsaglia's birthday spacings: m = 2¹⁰ birthdays in 2²⁴ days, 400 years, duplicates ~ Poisson(400·16)."""
    m, days, years = 2 ** 10, 2 ** 24, 400
    u = philox.uniforms(m * years, key=(1, 2), c1=0, c2=philox.stream_word(1, 2, 0)).reshape(years, m)
    b = np.sort(np.floor(u * days).astype(np.int64), axis=1)
    sp = np.sort(np.diff(b, axis=1), axis=1)
    dup = int((np.diff(sp, axis=1) == 0).sum())
    lam = years * m ** 3 / (4 * days)
    assert abs(dup - lam) < 5 * np.sqrt(lam), f"{dup} duplicate spacings, expected {lam:.0f}"


def test_counter_words_and_keys_give_independent_streams():
    base = philox.standard_normals(10_000, key=(1, 2), c1=0, c2=0)
    for kw in (dict(key=(1, 3)), dict(key=(2, 2)), dict(key=(1, 2), c1=1), dict(key=(1, 2), c2=1),
               dict(key=(1, 2), c0_start=5000)):
        other = philox.standard_normals(10_000, **kw)
        assert abs(np.corrcoef(base, other)[0, 1]) < 5 / 100
        assert not np.any(base == other)


def test_draws_are_addressed_by_counter():
    z = philox.standard_normals(100, key=(4, 5), c1=6, c2=7)
    np.testing.assert_array_equal(philox.standard_normals(40, key=(4, 5), c1=6, c2=7, c0_start=30), z[60:100])
    np.testing.assert_array_equal(philox.standard_normals(5, key=(4, 5), c1=6, c2=7), z[:5])


def test_stream_word_and_bad_input():
    assert philox.stream_word(0, 0, 0) == 0
    assert philox.stream_word(1, philox.SOURCE_IDS["instability"], 1) == 0x131
    with pytest.raises(ValueError, match="axis must be an integer in"):
        philox.stream_word(0, 1, 16)
    with pytest.raises(ValueError, match="sensor must be an integer in"):
        philox.stream_word(-1, 1, 0)
    with pytest.raises(ValueError, match="c0 must be a 32-bit unsigned integer"):
        philox.philox4x32_10(2 ** 32, 0, 0, 0, 0, 0)
    with pytest.raises(ValueError, match="k1 must be a 32-bit unsigned integer"):
        philox.philox4x32_10(0, 0, 0, 0, 0, -1)
    with pytest.raises(ValueError, match="n must be an integer >= 0"):
        philox.standard_normals(-1)
    with pytest.raises(ValueError, match="key must be two 32-bit words"):
        philox.uniforms(3, key=(1, 2, 3))
    with pytest.raises(ValueError, match="must stay below 2"):
        philox.uniforms(10, c0_start=2 ** 32 - 2)
    assert philox.standard_normals(0).shape == (0,)


def test_philox_keys_follow_the_rng_rule():
    """mtcal.core.rng: keys hashed from (seed, stream, …) or from a caller's generator (its next spawn)."""
    from mtcal.core import rng

    k = rng.philox_key(7, 3)
    assert k == rng.philox_key(7, 3) and k != rng.philox_key(7, 4) and k != rng.philox_key(8, 3)
    assert all(0 <= w < 2 ** 32 for w in k)
    g = np.random.default_rng(11)
    first, second = rng.spawn_philox_key(g), rng.spawn_philox_key(g)
    assert first != second and first == rng.spawn_philox_key(np.random.default_rng(11))
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        rng.spawn_philox_key(11)
    with pytest.raises(ValueError, match="expected integers >= 0"):
        rng.philox_key(-1, 0)
