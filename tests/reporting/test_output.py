import numpy as np
import pandas as pd
import pytest

from mtcal.reporting import output


def test_figures_and_tables_are_byte_stable(tmp_path, monkeypatch):
    monkeypatch.setenv("MTCAL_OUTPUT_DIR", str(tmp_path))
    output.setup_matplotlib()
    import matplotlib.pyplot as plt

    blobs = []
    for _ in range(2):
        fig, ax = plt.subplots()
        ax.plot(np.arange(5), np.arange(5) ** 2)
        output.save_figure(fig, "F-test")
        blobs.append((tmp_path / "figures" / "F-test.png").read_bytes())
    assert blobs[0] == blobs[1]
    df = pd.DataFrame({"a": [1.0 / 3.0], "b": ["x"]})
    path = output.save_table(df, "T-test")
    assert path.read_text() == "a,b\n0.333333,x\n"


def test_run_size(monkeypatch):
    monkeypatch.setenv("MTCAL_SIZE", "ci")
    assert output.run_size() == "ci"
    monkeypatch.setenv("MTCAL_SIZE", "huge")
    with pytest.raises(ValueError, match="MTCAL_SIZE must be one of"):
        output.run_size()


def test_bad_artifact_id(tmp_path, monkeypatch):
    monkeypatch.setenv("MTCAL_OUTPUT_DIR", str(tmp_path))
    with pytest.raises(ValueError, match="artifact_id must be"):
        output.save_table(pd.DataFrame({"a": [1]}), "../x")
    with pytest.raises(TypeError, match="df must be a pandas DataFrame"):
        output.save_table([1, 2], "T")


def test_run_size_parameter_wins_over_environment(monkeypatch):
    monkeypatch.setenv("MTCAL_SIZE", "ci")
    assert output.run_size("full") == "full" and output.run_size(None) == "ci"
    monkeypatch.delenv("MTCAL_SIZE")
    assert output.run_size() == "full"
    with pytest.raises(ValueError, match=r"SIZE must be one of \('ci', 'full'\) or None, got 'big'"):
        output.run_size("big")


def test_output_dir_env_then_checkout(tmp_path, monkeypatch):
    monkeypatch.setenv("MTCAL_OUTPUT_DIR", str(tmp_path))
    assert output.output_dir() == tmp_path
    monkeypatch.delenv("MTCAL_OUTPUT_DIR")
    root = output.output_dir()
    assert (root / "pyproject.toml").is_file() and (root / "notebooks").is_dir()  # running from the checkout
