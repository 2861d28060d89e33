import matplotlib
import numpy as np
import pandas as pd
import pytest

from mtcal.core.units import DEG
from mtcal.reporting import compare
from mtcal.studies import conventions

matplotlib.use("Agg")


def test_below_hides_rounding_noise_only():
    assert conventions.below(4.4e-16, 1e-12) == conventions.below(0.0, 1e-12) == "< 1e-12"
    assert conventions.below(7.06e-4, 1e-12) == "0.000706"
    with pytest.raises(ValueError, match="value must be finite"):
        conventions.below(float("nan"), 1e-12)


def test_display_round_removes_negative_zero():
    df = conventions.display_round(pd.DataFrame({"x": [-1e-17, -0.00049, 1.23456], "s": ["a", "b", "c"]}), 3)
    assert [f"{v:.3f}" for v in df["x"]] == ["0.000", "0.000", "1.235"]


def test_resolve_parameters_defaults_and_errors():
    p = conventions.resolve_parameters("full", **conventions.PARAMETER_DEFAULTS)
    assert (p["n_trials"], p["allan_hours"]) == (8, 8.0)
    assert conventions.resolve_parameters("ci", n_trials=2, allan_hours=0.5)["n_trials"] == 2
    with pytest.raises(ValueError, match="SIZE must be one of"):
        conventions.resolve_parameters("huge")
    with pytest.raises(ValueError, match="installation_error_deg must be three finite angles"):
        conventions.resolve_parameters("ci", installation_error_deg=(30.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="unknown parameter"):
        conventions.resolve_parameters("ci", gyro_grade="industrial")
    with pytest.raises(ValueError, match="delta_accel_g"):
        conventions.resolve_parameters("ci", delta_accel_g=-1e-4)


def test_eq13_rank_not_condition_number():
    out = conventions.eq13_position_count()
    assert out["table"]["rank of A_s A_sᵀ"].tolist() == [3, 4, 4]
    assert out["table"]["σ_min / σ_max"].iloc[0] == "< 1e-12"
    assert not out["three_accepted"] and out["min_positions"] == 4
    assert all(r["holds"] and r["role"] == "erratum" for r in out["rows"])


def test_eq4_sign_error_and_axis_conflict():
    eq4 = conventions.eq4_coupling_table(np.array([0.3, -0.2, 0.5]) * DEG)
    assert eq4["sign_error"] and eq4["max_err_corrected_rad"] < 0.01 * eq4["max_exact_rad"]
    axes = conventions.axis_assignment_table()
    assert axes["conflict"] and axes["eq8_axes"] == {"x": "pitch", "y": "roll", "z": "yaw"}


def test_printed_matrices_and_eq1():
    m = conventions.printed_matrices_table()
    assert m["det_turntable"] < 0 and abs(m["det_windtunnel"] - 1) > 1e-3
    eq1 = conventions.eq1_orthogonality_table()
    assert eq1["table"].iloc[1, 1:].tolist() == [1.0, 1.0, 1.0] and eq1["max_deviation"] > 0.1


def test_eq3_parameter_change_propagates_to_title_and_rows():
    a = conventions.eq3_erratum(1e-4 * 9.80665, grid_deg=np.linspace(-89, 89, 31))
    b = conventions.eq3_erratum(1e-3 * 9.80665, grid_deg=np.linspace(-89, 89, 31))
    assert a["rel_err_printed"] > 0.1 and a["rel_err_corrected"] < 10 * 1e-4 * 57.3
    assert b["rel_err_corrected"] > 5 * a["rel_err_corrected"]  # second order grows with ΔA
    assert "5.7e-03" in a["rows"][1]["claim"] and "5.7e-02" in b["rows"][1]["claim"]
    fig_a, fig_b = conventions.eq3_erratum_figure(a), conventions.eq3_erratum_figure(b)
    assert "1.0e-04 g" in fig_a._suptitle.get_text() and "1.0e-03 g" in fig_b._suptitle.get_text()


def test_allan_check_recovers_noise_and_labels():
    p = conventions.resolve_parameters("ci", n_trials=2, allan_hours=0.5)
    out = conventions.allan_check(p["gyro_arw_rad_s_rt_hz"], p["gyro_rrw_rad_s_rt_s"], 10.0, 0.5, 2, 7)
    assert abs(out["n_ratio"] - 1) < 0.2
    fig = conventions.allan_figure(out)
    assert "2 static records" in fig.axes[0].get_title()


def test_what_if_reports_instead_of_raising():
    rows = conventions.eq3_erratum(0.05 * 9.80665, grid_deg=np.linspace(-89, 89, 31))["rows"]
    table = compare.comparison_table(rows)
    enforce = compare.at_paper_settings({"delta_accel_g": 0.05}, conventions.PARAMETER_DEFAULTS)
    assert enforce is False
    assert "claims hold" in compare.check_claims(table, enforce=enforce)
