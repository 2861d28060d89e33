"""Command-line entry point ``mtcal`` (subcommands run the methods on a user's log).

Each subcommand lives in its own module exposing ``register(subparsers)``,
which adds an ``argparse`` parser whose ``func(args) -> int`` runs it; the
modules are listed once, as a tuple in :func:`build_parser`. Every problem with the
user's files, arguments or output paths is reported as one line
``mtcal: error: …`` on stderr with exit status 2 — never a traceback.
Set ``MTCAL_DEBUG=1`` to let unexpected exceptions propagate (tests do).
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import warnings

from mtcal.core.allocator import keep_freed_memory

__all__ = ["build_parser", "main", "HelpFormatter"]

#: Options whose value may start with a minus sign (vectors): ``--axis -0.3,0,0.95`` works.
VECTOR_OPTIONS = ("--axis", "--gyro-scale", "--accel-scale")
_NUMBER = re.compile(r"^-(\d|\.\d)")


class HelpFormatter(argparse.RawDescriptionHelpFormatter):
    """``--help`` of every ``mtcal`` command: descriptions and epilogs as written, each option's default shown.

    An option whose help does not state its default itself gets `` (default: %(default)s)`` appended, as
    :class:`argparse.ArgumentDefaultsHelpFormatter` does, except where there is nothing to show (``None``,
    ``False``, ``""``, ``[]``: such options state their behaviour when omitted in their help text).
    """

    def _get_help_string(self, action):
        text = action.help or ""
        if (text is argparse.SUPPRESS or not action.option_strings or "(default" in text
                or action.default is argparse.SUPPRESS or action.default in (None, False, "", [])):
            return text
        return text + " (default: %(default)s)"


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``mtcal: error: …`` and exit status 2; help with defaults (:class:`HelpFormatter`)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str):  # noqa: D401 - argparse API
        self.exit(2, f"mtcal: error: {message} (see '{self.prog} --help')\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="mtcal", description=__doc__.splitlines()[0],
                     formatter_class=HelpFormatter,
                     epilog="run 'mtcal COMMAND --help' for the log schema, units and an example")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    from mtcal.cli import apply, attitude, axis, calibrate, compare, rests, run, sweep  # one import + one tuple entry per command

    for module in (rests, calibrate, axis, attitude, apply, sweep, run, compare):
        module.register(sub)
    run.register_reproduce(sub)  # `mtcal reproduce ID`: one artifact from the Monte Carlo cache
    return parser


def _join_negative_vectors(argv: list[str]) -> list[str]:
    """``--axis -0.3,0,1`` → ``--axis=-0.3,0,1`` (argparse would read the value as an option)."""
    out, i = [], 0
    while i < len(argv):
        tok = argv[i]
        if tok in VECTOR_OPTIONS and i + 1 < len(argv) and _NUMBER.match(argv[i + 1]):
            out.append(f"{tok}={argv[i + 1]}")
            i += 2
            continue
        out.append(tok)
        i += 1
    return out


def _one_line(exc: BaseException) -> str:
    """The message on one line, non-printable characters (e.g. from a binary file) replaced by '?'."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    return "".join(c if c.isprintable() else "?" for c in text)[:500]


def main(argv: list[str] | None = None) -> int:
    """Run ``mtcal`` with ``argv`` (default ``sys.argv[1:]``); returns the exit status.

    The program's entry point: it also lets glibc's malloc reuse the memory a command frees
    (:func:`mtcal.core.allocator.keep_freed_memory`: a command on a long log allocates and frees many
    column-sized temporaries; on the 2-vCPU bench VM fresh pages were a third of the CPU of
    ``mtcal attitude`` on the 1-hour log).
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    args = parser.parse_args(_join_negative_vectors(argv))
    debug = os.environ.get("MTCAL_DEBUG", "") not in ("", "0")
    keep_freed_memory()
    try:
        with warnings.catch_warnings():
            if not debug:
                warnings.simplefilter("ignore")
            import numpy as np

            with np.errstate(all="ignore" if not debug else "warn"):
                return int(args.func(args) or 0)
    except BrokenPipeError:  # e.g. `mtcal rests LOG | head`: stop quietly (Python docs' recipe)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except (ValueError, TypeError, OSError) as exc:
        print(f"mtcal: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("mtcal: error: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # noqa: BLE001 - never a traceback for a user's input
        if debug:
            raise
        print(f"mtcal: error: cannot process this input ({type(exc).__name__}: {_one_line(exc)}); "
              f"set MTCAL_DEBUG=1 for a traceback", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
