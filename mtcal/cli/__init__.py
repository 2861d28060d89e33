"""The ``mtcal`` command line: the papers' methods on a user's own log.

Subcommands: ``rests`` (static intervals and measured levels), ``calibrate``
(six-position installation-error calibration, ``--out Q.json``), ``apply``
(calibrated attitude from ``Q.json``), ``attitude`` (QNCF attitude), ``axis``
(rotation axis from rests at three tilts), ``angle`` (EKF rotation angle about
an axis). One log reader (:mod:`mtcal.cli.logio`) serves every command. A problem
with the user's files or arguments is a ``ValueError`` (or ``OSError``), reported by
:func:`main` as one line ``mtcal: error: …``.
"""

from mtcal.cli.main import build_parser, main

__all__ = ["main", "build_parser"]
