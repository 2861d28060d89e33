"""Shared pieces of the sweep tests: the small wind-tunnel attitude sweep spec."""

WINDTUNNEL_SPEC = """
[sweep]
name = "{name}"
evaluator = "attitude"
seed = {seed}
trials = {trials}
block_trials = {block}
[fixed]
motion = "windtunnel"
filters = {filters}
fs_hz = 100.0
hold_s = 0.5
speed = 5.0
vibration_hz = 20.0
[grid]
grade = ["industrial", "consumer"]
vibration_m_s2 = {vibration}
"""


def windtunnel_spec_text(*, name: str, seed: int, trials: int, block: int, filters: str, vibration: str) -> str:
    """TOML text of a small wind-tunnel attitude sweep (2 grades x 2 vibration levels, 100 Hz, 0.5 s holds).

    ``filters`` and ``vibration`` are TOML arrays as text, e.g. ``'["mahony", "vqf"]'``, ``"[0.0, 2.0]"``.
    """
    return WINDTUNNEL_SPEC.format(name=name, seed=seed, trials=trials, block=block, filters=filters,
                                  vibration=vibration)
