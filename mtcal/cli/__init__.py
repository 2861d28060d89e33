"""The ``mtcal`` command line: the papers' methods on a user's own log.

Subcommands: ``calibrate`` (six-position installation-error calibration), ``axis``
(rotation axis from three rests), ``angle`` (EKF rotation angle about an axis).
"""

from .main import UserInputError, build_parser, main

__all__ = ["main", "build_parser", "UserInputError"]
