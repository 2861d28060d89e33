"""Running ``mtcal`` in-process in a test: the exit code and the captured output, the one-line refusal, and an
identity calibration file to edit."""

import json

import numpy as np

from mtcal import cli


def run(args, capsys):
    """``mtcal ARGS`` in-process: ``(exit code, stdout, stderr)``."""
    code = cli.main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def refused(code, err, *needles):
    """A refusal by the rule: exit 2, one ``mtcal: error:`` line, no traceback, each of ``needles`` in it."""
    assert code == 2, err
    assert err.startswith("mtcal: error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    for n in needles:
        assert n in err, err


def calibration_file(tmp_path, **fields):
    """A calibration file as ``mtcal calibrate`` writes it (identity ``q_hat``), ``fields`` replaced: its path."""
    doc = {"format": "mtcal-calibration/2", "format_version": 2, "q_hat": np.eye(4).tolist(),
           "residual_deg": [0.01] * 6, "positions_deg": [[0.0, 0.0, 0.0]] * 6,
           "installation_angles_1sigma_deg": {"alpha1_z": 0.1, "alpha2_y": 0.1, "alpha3_x": 0.1},
           "mounting_quaternion_q_bs": [1.0, 0.0, 0.0, 0.0], **fields}
    path = tmp_path / "Q.json"
    path.write_text(json.dumps(doc))
    return path
