"""mtcal.core.rng: the keyed streams and the helpers that replaced the studies' direct numpy seeding
(each equal, bit for bit, to the expression it replaced)."""

import numpy as np
import pytest

from mtcal.core.rng import child_rngs, rng_copy, spawn_philox_key, stream_key, stream_rng, trial_rng


def _bits(g, n=8):
    return g.bit_generator.random_raw(n)


@pytest.mark.parametrize("seed", [0, 1, 5, 2023, 2**32 + 7, 2**64 + 3])
def test_stream_zero_is_the_bare_integer_seed(seed):
    # constrained.py, conventions.py: np.random.default_rng(seed) -> stream_rng(seed, 0)
    assert np.array_equal(_bits(np.random.default_rng(seed)), _bits(stream_rng(seed, 0)))


@pytest.mark.parametrize("seed", [0, 2023])
def test_sequence_key_equals_stream_rng(seed):
    # predictive.py / runs.py: default_rng(SeedSequence([seed, s])) -> stream_rng(seed, s)
    for s in (0, 3, 11, 300, 302):
        assert np.array_equal(_bits(np.random.default_rng(np.random.SeedSequence([seed, s]))), _bits(stream_rng(seed, s)))
    # default_rng([seed, 12, t]) == trial_rng(seed, 12, t)
    assert np.array_equal(_bits(np.random.default_rng([seed, 12, 4])), _bits(trial_rng(seed, 12, 4)))


def test_child_rngs_is_numpy_spawn():
    old = np.random.default_rng(np.random.SeedSequence([7, 301])).spawn(4)
    new = child_rngs(stream_rng(7, 301), 4)
    assert [_bits(a).tolist() for a in old] == [_bits(b).tolist() for b in new]


def test_child_rngs_continues_the_spawn_count():
    g_old, g_new = np.random.default_rng(3), stream_rng(3, 0)
    g_old.spawn(2)
    child_rngs(g_new, 2)
    old, new = g_old.spawn(3), child_rngs(g_new, 3)           # children 2, 3, 4 of each
    assert [_bits(a).tolist() for a in old] == [_bits(b).tolist() for b in new]
    nested_old, nested_new = old[1].spawn(3), child_rngs(new[1], 3)
    assert [_bits(a).tolist() for a in nested_old] == [_bits(b).tolist() for b in nested_new]


def test_child_of_fresh_stream_is_a_keyed_stream():
    for i, c in enumerate(child_rngs(stream_rng(7, 300), 3)):
        assert np.array_equal(_bits(c), _bits(stream_rng(7, 300, 0, 0, i)))


def test_child_rngs_bad_input():
    with pytest.raises(ValueError, match="n must be an integer >= 0"):
        child_rngs(stream_rng(0, 1), -1)
    with pytest.raises(ValueError, match="n must be an integer >= 0"):
        child_rngs(stream_rng(0, 1), True)
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        child_rngs(np.random.SeedSequence(1), 2)


def test_rng_copy_equals_the_old_seed_sequence_snapshot():
    # tan2022.runs.GyroTrials: SeedSequence(entropy, spawn_key=…, pool_size=…, n_children_spawned=…)
    g = stream_rng(5, 10)
    g.spawn(1)
    ss = g.bit_generator.seed_seq
    old = np.random.Generator(np.random.PCG64(np.random.SeedSequence(
        ss.entropy, spawn_key=ss.spawn_key, pool_size=ss.pool_size, n_children_spawned=ss.n_children_spawned)))
    new = rng_copy(g)
    assert np.array_equal(_bits(old), _bits(new))
    assert spawn_philox_key(old) == spawn_philox_key(new) == spawn_philox_key(g)


def test_rng_copy_leaves_the_original_untouched():
    g = stream_rng(5, 10)
    c = rng_copy(g)
    child_rngs(c, 3)
    assert g.bit_generator.seed_seq.n_children_spawned == 0
    with pytest.raises(TypeError, match="rng must be a numpy.random.Generator"):
        rng_copy(np.random.PCG64(1))


def test_stream_key_rejects_negative_and_bool():
    with pytest.raises(ValueError, match="expected integers >= 0"):
        stream_key(1, -2)
    with pytest.raises(ValueError, match="expected integers >= 0"):
        stream_rng(True, 2)
