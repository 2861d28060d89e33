"""Shared pytest fixtures."""

import numpy as np
import pytest


@pytest.fixture
def rng() -> np.random.Generator:
    """A seeded generator: every random draw in tests goes through one."""
    return np.random.default_rng(12345)
