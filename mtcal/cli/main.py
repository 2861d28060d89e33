"""Command-line entry point ``mtcal`` (subcommands run the methods on a user's log).

Each subcommand lives in its own module exposing ``register(subparsers)``,
which adds an ``argparse`` parser whose ``func(args) -> int`` runs it.
Errors in user files are reported as one line ``mtcal: error: …`` on stderr
with exit status 2.
"""

from __future__ import annotations

import argparse
import sys

__all__ = ["UserInputError", "build_parser", "main"]


class UserInputError(ValueError):
    """A problem with the user's files or arguments (reported without a traceback)."""


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="mtcal", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    from mtcal.cli import axis, calibrate, compare, run  # subcommand modules import UserInputError from here

    for module in (calibrate, axis, run, compare):
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except (UserInputError, ValueError, TypeError, FileNotFoundError) as exc:
        print(f"mtcal: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
