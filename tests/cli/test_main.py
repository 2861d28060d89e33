import pytest

from mtcal import cli


def test_help_lists_program(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["--help"])
    assert exc.value.code == 0
    assert "usage: mtcal" in capsys.readouterr().out


def test_missing_subcommand_is_an_error(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main([])
    assert exc.value.code == 2


HEAVY = ("numba", "scipy", "pandas", "matplotlib")
_PROBE = """
import runpy, sys
sys.argv = ["mtcal"] + sys.argv[1:]
try:
    runpy.run_module("mtcal", run_name="__main__")
except SystemExit as exc:
    code = exc.code
else:
    code = None
print("exit", code, "loaded", *sorted(m for m in {heavy!r} if m in sys.modules), file=sys.stderr)
"""


@pytest.mark.parametrize("argv", [["--help"], ["calibrate", "--help"], ["apply", "--help"], ["axis", "--help"],
                                  ["angle", "--help"], ["rests", "--help"], ["sweep", "--help"], ["calibrate"]])
def test_parsing_loads_no_heavy_library(argv):
    """``mtcal --help`` (and argument parsing, up to a usage error) imports neither numba, scipy, pandas
    nor matplotlib: they load only when a subcommand runs."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = Path(cli.__file__).resolve().parents[2]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.run([sys.executable, "-c", _PROBE.format(heavy=HEAVY), *argv], capture_output=True,
                          text=True, env=env, timeout=120)
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith("exit 0" if "--help" in argv else "exit 2"), proc.stderr
    assert last.split("loaded")[1].split() == [], f"mtcal {' '.join(argv)} loaded: {last}"


def test_main_tells_the_allocator_to_keep_freed_memory(monkeypatch, capsys):
    """main() calls mtcal.core.allocator.keep_freed_memory (tested there) before the command runs."""
    import sys

    main_mod = sys.modules["mtcal.cli.main"]
    calls = []
    monkeypatch.setattr(main_mod, "keep_freed_memory", lambda: calls.append(1))
    assert main_mod.main(["rests", "no_such_log.csv"]) == 2
    assert calls == [1] and "mtcal: error:" in capsys.readouterr().err


def _subparsers():
    import argparse

    from mtcal.cli.main import build_parser

    action = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return action.choices


@pytest.mark.parametrize("command", sorted(_subparsers()))
def test_help_states_every_option_default(command, capsys):
    """Every option of every command says its default in --help: '(default: …)' appended by the formatter for
    a value, or written in the help text for an option whose omission means something (no file, measured …);
    flags (store_true), required options and the old hidden spellings excepted."""
    import argparse

    parser = _subparsers()[command]
    for action in parser._actions:
        if (not action.option_strings or action.help == argparse.SUPPRESS or action.required
                or isinstance(action, (argparse._HelpAction, argparse._StoreTrueAction, argparse._AppendAction))):
            continue
        text = parser._get_formatter()._get_help_string(action) % {"default": action.default}
        assert "(default: " in text, f"mtcal {command} {action.option_strings[0]}: {text!r}"
    with pytest.raises(SystemExit):
        cli.main([command, "--help"])
    out = " ".join(capsys.readouterr().out.split())
    expected = {"attitude": "(default: attitude.csv)", "angle": "(default: angle.csv)",
                "apply": "(default: body_attitude.csv)", "rests": "(default: none, the table is only printed)",
                "calibrate": "(default: none, the result is only printed)"}
    assert expected.get(command, "(default: ") in out


def test_max_so4_distance_help_is_the_procedure_default():
    from mtcal.cli.calibrate import MAX_SO4_DISTANCE_TEXT
    from mtcal.systems.installation import MAX_SO4_DISTANCE

    assert float(MAX_SO4_DISTANCE_TEXT) == MAX_SO4_DISTANCE
