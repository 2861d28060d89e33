"""s18: a CSV whose last row was cut short (logger killed) is read without it, noted on the log line; a short row
elsewhere is refused naming it; a decimal-comma value gets a hint about the separator."""

import pytest

from mtcal import cli
from mtcal.cli import logio
from tests.cli import logs


@pytest.fixture(scope="module")
def hinge_text(tmp_path_factory):
    path = logs.hinge_log().write(tmp_path_factory.mktemp("rows") / "hinge.csv")
    with open(path) as fh:
        return fh.read()


def test_truncated_last_row_dropped_with_a_note(hinge_text, tmp_path, capsys):
    path = tmp_path / "cut.csv"
    path.write_text(hinge_text.rstrip("\n")[:-30])            # the last row loses its last field(s)
    n_full = hinge_text.count("\n") - 1
    log = logio.read_log(path, logio.InputOptions(), need="raw")
    assert log.n == n_full - 1
    assert any(note.startswith("last row dropped: it has ") and "logger stopped mid-row?" in note
               for note in log.notes), log.notes
    assert cli.main(["rests", str(path)]) == 0
    assert "last row dropped" in capsys.readouterr().out


def test_short_row_inside_the_log_refused(hinge_text, tmp_path, capsys):
    lines = hinge_text.splitlines()
    path = tmp_path / "mid.csv"
    path.write_text("\n".join(lines[:5] + ["1.0,2.0"] + lines[5:]) + "\n")
    with pytest.raises(ValueError, match=r"mid.csv: not a readable CSV \(CSV parse error: Expected 7 columns, got 2: 1.0,2.0"):
        logio.read_log(path, logio.InputOptions(), need="raw")
    assert cli.main(["rests", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: ") and err.count("\n") == 1


def test_decimal_comma_hint(hinge_text, tmp_path):
    lines = hinge_text.splitlines()
    body = [line.replace(",", ";").replace(".", ",") for line in lines[1:]]
    path = tmp_path / "comma.csv"
    path.write_text(lines[0].replace(",", ";") + "\n" + "\n".join(body) + "\n")
    with pytest.raises(ValueError, match=r"non-numeric or NaN value in column 'time_s' at data row \d+ "
                                         r"\('[0-9]+,[0-9]+': a decimal comma\? write the log with a decimal point"):
        logio.read_log(path, logio.InputOptions(), need="raw")
