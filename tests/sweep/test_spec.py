"""Sweep spec: TOML parsing, grid order, validation errors naming the key."""

import pytest

from mtcal.sweep.spec import SweepSpec, load_spec, parse_spec

BASE = """
[sweep]
name = "t"
evaluator = "attitude"
seed = 3
trials = 10
block_trials = 4
[fixed]
motion = "roll"
filters = ["qncf", "mahony"]
[grid]
grade = ["industrial", "tactical", "consumer"]
vibration_m_s2 = [0.0, 2.5]
"""


def test_cells_are_the_product_in_written_order_last_key_fastest():
    spec = parse_spec(BASE)
    assert spec.n_cells == 6
    cells = spec.cells()
    assert [(c["grade"], c["vibration_m_s2"]) for c in cells[:3]] == [
        ("industrial", 0.0), ("industrial", 2.5), ("tactical", 0.0)]
    assert all(c["motion"] == "roll" and c["filters"] == ["qncf", "mahony"] for c in cells)
    assert spec.grid_values(5) == {"grade": "consumer", "vibration_m_s2": 2.5}
    assert spec.block_trials == 4


def test_fingerprints_track_what_changes_numbers():
    a = parse_spec(BASE)
    b = parse_spec(BASE.replace("trials = 10", "trials = 11"))
    c = parse_spec(BASE.replace("block_trials = 4", "block_trials = 5"))
    assert a.fingerprint() != b.fingerprint()
    assert a.fingerprint() == c.fingerprint()      # block size is checked separately
    assert a.cell_fingerprint(0) != a.cell_fingerprint(1)
    assert a.as_dict()["grid"]["grade"] == ["industrial", "tactical", "consumer"]


def test_load_spec_reads_a_file(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(BASE)
    assert load_spec(p).name == "t"
    with pytest.raises(FileNotFoundError, match="spec file not found"):
        load_spec(tmp_path / "missing.toml")


@pytest.mark.parametrize("old,new,match", [
    ("trials = 10", "trials = -3", r"sweep\.trials must be an integer in \[1, 10000000\], got -3"),
    ("trials = 10", "trials = 2.5", r"sweep\.trials must be an integer in \[1, 10000000\], got 2.5"),
    ("seed = 3", "seed = -1", r"sweep\.seed must be an integer >= 0"),
    ("block_trials = 4", "block_trials = 0", r"sweep\.block_trials must be a positive integer"),
    ('name = "t"', 'name = "a b"', r"sweep\.name must be"),
    ('evaluator = "attitude"', 'evaluator = "nope"', r"sweep\.evaluator must be one of \['attitude'"),
    ('grade = ["industrial", "tactical", "consumer"]', 'grade = ["industrial", "gold"]',
     r"grid\.grade must be one of \['consumer'"),
    ('grade = ["industrial", "tactical", "consumer"]', 'grade = []', r"grid\.grade must be a non-empty array"),
    ('grade = ["industrial", "tactical", "consumer"]', 'grade = "industrial"', r"grid\.grade must be a non-empty"),
    ('grade = ["industrial", "tactical", "consumer"]', 'grade = ["tactical", "tactical"]', r"grid\.grade has repeated"),
    ('motion = "roll"', 'motion = "yaw"', r"fixed\.motion must be one of \['aoa', 'roll', 'windtunnel'\]"),
    ('motion = "roll"', 'colour = "red"', r"fixed\.colour is not a parameter of evaluator 'attitude'"),
    ('motion = "roll"', 'grade = "tactical"', r"grid\.grade is also in \[fixed\]"),
    ("vibration_m_s2 = [0.0, 2.5]", "vibration_m_s2 = [0.0, -1.0]", r"grid\.vibration_m_s2 must be a number in \[0, 50\]"),
    ('filters = ["qncf", "mahony"]', 'filters = ["qncf", "ekf"]', r"fixed\.filters must be a non-empty list"),
    ("[fixed]", "[fixed]\ngain_qncf = 0.0", r"fixed\.gain_qncf must be a number in \(0"),
    ("[sweep]", "[sweep]\ncores = 4", r"sweep\.cores is not a valid key"),
    ("[grid]", "[other]\nx = 1\n[grid]", r"unknown table \[other\]"),
    ('name = "t"\n', "", r"sweep\.name is missing"),
    ("trials = 10", "trials = [", r"not valid TOML"),
    ("trials = 10", "trials = 1000000000000", r"sweep\.trials must be an integer in \[1, 10000000\], got 1000000000000"),
    ("vibration_m_s2 = [0.0, 2.5]", "vibration_m_s2 = [" + ", ".join(str(0.001 * k) for k in range(40000)) + "]",
     r"\[grid\] makes 120000 cells \(3 x 40000\), more than 100000 in one sweep; split the grid"),
])
def test_errors_name_the_key(old, new, match):
    assert old in BASE
    with pytest.raises(ValueError, match=match):
        parse_spec(BASE.replace(old, new, 1))


def test_missing_sweep_table_and_type_errors():
    with pytest.raises(ValueError, match=r"missing \[sweep\] table"):
        parse_spec("[grid]\nx = [1]\n")
    with pytest.raises(TypeError, match="text must be a str"):
        parse_spec(b"[sweep]")
    with pytest.raises(ValueError, match=r"fixed\.n_positions must be an integer in \[4, 12\], got 3"):
        SweepSpec("x", "six_position", 1, 2, fixed={"n_positions": 3})
    with pytest.raises(ValueError, match=r"vibration_hz must be .* \(evaluator default; set it in \[fixed\]\)"):
        SweepSpec("x", "attitude", 1, 2, fixed={"fs_hz": 50.0})
