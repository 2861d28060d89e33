"""Reporting: the papers' numbers, paper-vs-mtcal comparison with Monte Carlo bands, output files.

Reporting imports only :mod:`mtcal.core`; the studies build their comparison rows with it.
Notebook execution and what-if runs are :mod:`mtcal.runs` (above every layer they run).

The public names of every submodule are re-exported here (see ``__all__``).
"""

from typing import TYPE_CHECKING

from mtcal.core.lazy import lazy_attributes

if TYPE_CHECKING:  # the eager imports, for type checkers and tests/test_import_graph.py
    from . import compare, output, paper_numbers
    from . import binomial, fidelity, leak
    from .binomial import coin_flip, CoinFlip, wilson_interval
    from .paper_numbers import available, heldout, load, paper_dir, split, training, value
    from .compare import (at_paper_settings, band_description, band_record, band_row, band_summary, band_text,
                          cell_text, check_bands, check_claims, claim, claims_summary, comparison_row, comparison_table,
                          COMPARISON_COLUMNS, consistency, credible_interval, describe, draw_count, is_missing, KINDS,
                          prediction_summary, role_summary, ROLES, SOURCES, spread_text)
    from .output import output_dir, run_size, save_figure, save_table, setup_matplotlib, show_table

__all__ = ["paper_numbers", "compare", "output", "fidelity", "leak", "binomial", "paper_dir", "available", "load",
           "value", "split", "training", "heldout", "COMPARISON_COLUMNS",
           "comparison_row", "comparison_table", "band_summary", "claims_summary", "band_record", "band_row",
           "band_text", "describe", "claim", "consistency", "ROLES", "KINDS", "SOURCES", "at_paper_settings",
           "check_claims", "role_summary", "prediction_summary", "check_bands", "credible_interval", "spread_text",
           "band_description", "is_missing", "draw_count", "cell_text", "coin_flip", "CoinFlip", "wilson_interval",
           "run_size", "output_dir", "setup_matplotlib", "save_figure", "save_table", "show_table"]

#: Submodules, loaded on first attribute access (``import mtcal`` stays light for the CLI).
_SUBMODULES = ('compare', 'output', 'paper_numbers', 'fidelity', 'leak', 'binomial')
#: Re-exported name → submodule defining it (imported on first access).
_EXPORTS = {
    "COMPARISON_COLUMNS": "compare", "KINDS": "compare", "ROLES": "compare", "SOURCES": "compare",
    "at_paper_settings": "compare", "band_record": "compare", "band_row": "compare", "band_summary": "compare",
    "band_text": "compare", "check_claims": "compare", "claim": "compare", "claims_summary": "compare",
    "comparison_row": "compare", "comparison_table": "compare", "consistency": "compare", "describe": "compare",
    "prediction_summary": "compare", "role_summary": "compare", "check_bands": "compare",
    "credible_interval": "compare", "spread_text": "compare", "band_description": "compare", "is_missing": "compare",
    "draw_count": "compare", "cell_text": "compare", "coin_flip": "binomial", "CoinFlip": "binomial",
    "wilson_interval": "binomial", "output_dir": "output", "run_size": "output",
    "save_figure": "output", "save_table": "output", "setup_matplotlib": "output", "show_table": "output",
    "available": "paper_numbers", "heldout": "paper_numbers", "load": "paper_numbers", "paper_dir": "paper_numbers",
    "split": "paper_numbers", "training": "paper_numbers", "value": "paper_numbers",
}

__getattr__, __dir__ = lazy_attributes(globals(), _SUBMODULES, _EXPORTS)
