"""Reporting: the papers' numbers, paper-vs-mtcal comparison with Monte Carlo bands, output files.

Reporting imports only :mod:`mtcal.core`; the studies build their comparison rows with it.
Notebook execution and what-if runs are :mod:`mtcal.runs` (above every layer they run).

The public names of every submodule are re-exported here (see ``__all__``).
"""

from . import compare, output, paper_numbers
from . import fidelity, leak
from .paper_numbers import available, heldout, load, paper_dir, split, training, value
from .compare import (at_paper_settings, band_record, band_row, band_summary, band_text, check_claims, claim,
                      claims_summary, comparison_row, comparison_table, COMPARISON_COLUMNS, consistency, describe,
                      KINDS, prediction_summary, role_summary, ROLES, SOURCES)
from .output import output_dir, run_size, save_figure, save_table, setup_matplotlib, show_table

__all__ = ["paper_numbers", "compare", "output", "fidelity", "leak", "paper_dir", "available", "load", "value",
           "split", "training", "heldout", "COMPARISON_COLUMNS",
           "comparison_row", "comparison_table", "band_summary", "claims_summary", "band_record", "band_row",
           "band_text", "describe", "claim", "consistency", "ROLES", "KINDS", "SOURCES", "at_paper_settings",
           "check_claims", "role_summary", "prediction_summary",
           "run_size", "output_dir", "setup_matplotlib", "save_figure", "save_table", "show_table"]
