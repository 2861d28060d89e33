"""Pinned per-trial metrics of every simulation evaluator: restructuring an evaluator keeps its numbers.

Each case runs one evaluator on 2 cells × 2 trials, once through the engine's keyed streams
(:func:`mtcal.sweep.engine.run_block`) and once with a plain list of generators (one simulation
per trial), and hashes the metrics (sha256 of the float64 bytes, metric names sorted). The hashes
were computed on the code before the evaluators were written as one pass per layer (main bfccb2d).
"""

import hashlib

import numpy as np
import pytest

from mtcal.sweep.engine import run_block, trial_rngs
from mtcal.sweep.evaluators import get_evaluator

CASES = {
    "attitude": [dict(motion="roll", filters=["qncf", "mahony", "madgwick"], fs_hz=100.0, hold_s=1.0),
                 dict(motion="windtunnel", filters=["qncf"], fs_hz=100.0, vibration_m_s2=2.0, vibration_hz=20.0,
                      hold_s=1.0, gain_scale=1.5, gain_qncf=0.5)],
    "surface": [dict(filters=["rams_ekf", "qncf", "mahony"], fs_hz=100.0, span_deg=30.0),
                dict(filters=["qncf", "rams_ekf"], fs_hz=100.0, span_deg=30.0, lever_arm_m=0.5,
                     vibration_m_s2=1.0, vibration_hz=20.0, gain_rams_ekf=3.0)],
    "six_position": [dict(n_positions=4, fs_hz=100.0, rest_s=1.0),
                     dict(n_positions=7, fs_hz=100.0, rest_s=1.5, alpha_deg=[1.0, -2.0, 0.5])],
}

PINNED = {
    'attitude': '70d0083fb000c967a75daa243582c1c09b66cad80dfdc1e9e6f852186cd9426a',
    'surface': 'f894ebebb0a184fcb98a280515e097cbe63bd46fd9634cb7c6f4998b20ded3fd',
    'six_position': '878b65b2b36a25ffff5a69f2e33485241ab17547e59d873a26c4cef54e6d3771',
}


def _digest(blocks) -> str:
    h = hashlib.sha256()
    for out in blocks:
        for name in sorted(out):
            h.update(name.encode())
            h.update(np.ascontiguousarray(out[name], dtype=np.float64).tobytes())
    return h.hexdigest()


def _blocks(evaluator: str):
    ev = get_evaluator(evaluator)
    blocks = []
    for cell, params in enumerate(CASES[evaluator]):
        params = ev.resolve(params)
        blocks.append(run_block(evaluator, params, 11, cell, 0, 2))
        blocks.append(ev(params, trial_rngs(11, cell, 0, 2)))
    return blocks


@pytest.mark.parametrize("evaluator", sorted(CASES))
def test_evaluator_numbers_are_pinned(evaluator):
    assert _digest(_blocks(evaluator)) == PINNED[evaluator]
