"""Paper-vs-mtcal comparison rows, Monte Carlo bands, and scenario tables for display.

Every notebook reports its results through :func:`comparison_table`, with the
columns :data:`COMPARISON_COLUMNS`: ``artifact | quantity | paper | mtcal |
mc_band | paper_in_band | prior_band | prior_in_band | claim | holds | kind |
role | source | note | enforced | ref`` and the numeric band ends (``mc_low,
mc_high, prior_median, prior_low, prior_high``). The band columns are filled where
the mtcal number comes from a Monte Carlo: posterior-predictive median in
``mtcal``, its 95 % interval in ``mc_band``; the prior-predictive interval (the
baseline, parameters drawn from the prior) in ``prior_band``.

Every band carries its Monte Carlo draw count and kind (``mc_draws, mc_kind,
prior_draws, prior_kind``; :data:`BAND_KINDS`): a ``"95 % band"`` (the 2.5–97.5 %
points) rests on at least :data:`mtcal.core.metrics.MIN_BAND_DRAWS` draws; from fewer
draws the spread is the min–max ``"range"``, printed with its count
(``"range [a, b] (n=4)"``; :func:`mtcal.core.metrics.band_or_range` makes both); a
posterior interval computed on a parameter grid (no draws) is a ``"credible interval"``
(:func:`credible_interval`). A band given as a bare ``(low, high)`` pair, or as a dict
without ``n``, has an unknown count. :func:`check_bands` enforces the rule; :func:`comparison_table` runs it on every
table it builds, :func:`check_claims` and :mod:`mtcal.reporting.fidelity` on every table
they check or score, so no notebook prints, saves or scores a band that breaks it.

``role`` is the split role of the paper number (:data:`ROLES`: ``train``, ``tuned``,
``heldout``, ``input``, ``erratum``, ``not-compared`` as in
``paper_data/<key>_split.csv``, plus ``finding`` for our own results). ``kind``
says what a tested row is (:data:`KINDS`): ``claim`` (the paper's statement with its
threshold quoted in ``claim``, tested on numbers no fit read and no setting was chosen
against), ``in-sample`` (the paper's statement checked on numbers the model was fitted
or tuned on: it can fail, and a failing one prints "FAILS", but it is no confirmation)
or ``consistency`` (true by construction: a prior containing its grid, arithmetic on
printed numbers, a geometric identity). Neither in-sample nor consistency rows count as
claims.

>>> from mtcal.core import metrics
>>> row = comparison_row("wang2023cja_table06", "roll RMSE (deg)", 0.009, 0.0071, "<= 0.01", True,
...                      band=metrics.band_or_range([0.005, 0.007, 0.010]))
>>> row["paper_in_band"], row["kind"], row["role"], row["mc_band"], row["mc_draws"], row["mc_kind"]
(True, 'claim', 'heldout', 'range [0.005, 0.01] (n=3)', 3, 'range')
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np
import pandas as pd

from mtcal.core import metrics
from mtcal.core.validate import merge_parameters

__all__ = ["COMPARISON_COLUMNS", "DISPLAY_COLUMNS", "comparison_row", "comparison_table", "band_summary", "claims_summary",
           "band_record", "band_row", "band_text", "describe", "claim", "consistency", "in_sample",
           "ROLES", "KINDS", "SOURCES", "at_paper_settings", "check_claims", "role_summary", "prediction_summary",
           "BAND_KINDS", "BAND_COUNT_COLUMNS", "check_bands", "credible_interval", "spread_text", "band_description",
           "is_missing", "draw_count", "cell_text", "IMPLIED_MIN", "implied_by_training"]

#: A statement tested on a fitted model is no independent test when something else implies it: in the prior
#: predictive (parameters from the prior, one sensor set per draw), if it holds in at least this fraction of the
#: draws where every training statement holds, it is checked ``in-sample`` (the fit keeps those draws, so holding
#: confirms nothing); if it holds in at least this fraction of all draws, the model family implies it whatever
#: is fitted (kind ``consistency``). The 95 % of the bands.
IMPLIED_MIN = 0.95

COMPARISON_COLUMNS = ["artifact", "quantity", "paper", "mtcal", "mc_band", "paper_in_band", "prior_band",
                      "prior_in_band", "claim", "holds", "kind", "role", "source", "note", "enforced", "ref",
                      "mc_low", "mc_high", "prior_median", "prior_low", "prior_high", "mc_draws", "mc_kind",
                      "prior_draws", "prior_kind"]
#: What a band of a row is: the 2.5–97.5 % points of >= ``metrics.MIN_BAND_DRAWS`` Monte Carlo draws, the min–max
#: range of fewer draws (printed with its count), or a 95 % posterior credible interval computed by quadrature on a
#: parameter grid (no Monte Carlo draws, no count; :func:`credible_interval`).
BAND_KINDS = ("95 % band", "range", "credible interval")
#: Per band (``mc``: posterior predictive, ``prior``: prior predictive): its text, draw-count and kind columns.
BAND_COUNT_COLUMNS = {"mc": ("mc_band", "mc_draws", "mc_kind"), "prior": ("prior_band", "prior_draws", "prior_kind")}

#: The columns a notebook prints (the numeric band ends and bookkeeping stay in the saved CSV).
DISPLAY_COLUMNS = ["artifact", "quantity", "paper", "mtcal", "mc_band", "prior_band", "claim", "holds", "kind",
                   "role"]
#: What the paper number of a row is: its split role (``paper_data/<key>_split.csv``) or ``finding``
#: (a result of ours the paper does not state).
ROLES = ("train", "tuned", "heldout", "input", "erratum", "not-compared", "finding")
#: What a tested row is: the paper's claim (out of sample), the paper's statement checked in-sample (on numbers a fit
#: read or a setting was chosen against), or a check that holds by construction.
KINDS = ("claim", "in-sample", "consistency")
#: Who makes the claim in the row.
SOURCES = ("paper claim", "mtcal finding")


def _band(band, name):
    """(median or nan, low, high, draws or None, kind, text) of a band given as a dict or a pair; validated.

    A dict's ``n`` (draws) and ``kind`` (:data:`BAND_KINDS`, default ``"95 % band"``) are recorded; a
    pair, or a dict without ``n``, has an unknown count (``None``), which :func:`check_bands` rejects.
    """
    if isinstance(band, dict):
        low, high, med = band["low"], band["high"], band.get("median", np.nan)
        draws, kind = band.get("n"), band.get("kind", "95 % band")
    else:
        low, high = band
        med, draws, kind = np.nan, None, "95 % band"
    low, high, med = float(low), float(high), float(med)
    if not (np.isfinite(low) and np.isfinite(high)) or low > high:
        raise ValueError(f"{name} must be a finite (low, high) with low <= high, got ({low}, {high})")
    if draws is not None:
        if isinstance(draws, (bool, np.bool_)) or not isinstance(draws, (int, np.integer)) or draws < 1:
            raise ValueError(f"{name}['n'] must be a positive int (the Monte Carlo draws), got {draws!r}")
        draws = int(draws)
    if kind not in BAND_KINDS:
        raise ValueError(f"{name}['kind'] must be one of {BAND_KINDS}, got {kind!r}")
    if kind == "credible interval" and draws is not None:
        raise ValueError(f"{name} of kind 'credible interval' is computed on a grid, not from draws: "
                         f"expected no 'n', got {draws!r}")
    return med, low, high, draws, kind, spread_text(low, high, kind, draws)


def spread_text(low: float, high: float, kind: str = "95 % band", n: int | None = None,
                digits: int | None = None) -> str:
    """The printed form of a band: ``"[low, high]"``, ``"range [low, high] (n=…)"`` or ``"credible [low, high]"``.

    The one formatter of a band's ends (the ``mc_band``/``prior_band`` cells of
    :func:`comparison_row`, :func:`band_text`).

    Parameters
    ----------
    low, high : float
        The band's ends.
    kind : str
        One of :data:`BAND_KINDS`: a ``"95 % band"`` prints bare, a ``"range"`` with its draw
        count (``n=?`` when unknown), a ``"credible interval"`` as ``"credible [low, high]"``.
    n : int, optional
        Draw count (printed for a range).
    digits : int, optional
        Fixed decimals; default four significant digits.

    Raises
    ------
    ValueError
        ``kind`` not in :data:`BAND_KINDS`.

    Examples
    --------
    >>> spread_text(0.005, 0.01, "range", 3)
    'range [0.005, 0.01] (n=3)'
    >>> spread_text(1.0, 3.0, "range", 3, digits=4)
    'range [1.0000, 3.0000] (n=3)'
    >>> spread_text(0.1, 0.3, "credible interval")
    'credible [0.1, 0.3]'
    """
    if kind not in BAND_KINDS:
        raise ValueError(f"kind must be one of {BAND_KINDS}, got {kind!r}")
    ends = (f"{v:.4g}" if digits is None else f"{v:.{int(digits)}f}" for v in (low, high))
    text = "[{}, {}]".format(*ends)
    if kind == "range":
        return f"range {text} (n={'?' if n is None else n})"
    return f"credible {text}" if kind == "credible interval" else text


def credible_interval(low, high, median=np.nan) -> dict:
    """A 95 % posterior credible interval computed on a parameter grid, as a ``band=`` of :func:`comparison_row`.

    Quadrature over a grid posterior has no Monte Carlo draws (its error is the grid's resolution), so
    the band rule's draw count does not apply; the row records kind ``"credible interval"`` and prints
    ``"credible [low, high]"``.

    >>> comparison_row("a", "b (deg/s)", 0.2, 0.21, "", None, band=credible_interval(0.1, 0.3))["mc_band"]
    'credible [0.1, 0.3]'
    """
    return {"low": low, "high": high, "median": median, "kind": "credible interval"}


def _inside(paper, low, high):
    try:
        return bool(low <= float(paper) <= high)
    except (TypeError, ValueError):
        return None  # the paper gives no number to place in the band


def comparison_row(artifact: str, quantity: str, paper, mtcal, claim: str, holds: bool | None,
                   *, band=None, prior_band=None, role: str = "heldout", source: str = "paper claim",
                   kind: str | None = None, note: str = "", enforce: bool = True, ref: str = "") -> dict:
    """One row of the paper-vs-mtcal table.

    Parameters
    ----------
    artifact, quantity : str
        Artifact ID (``"wang2023cja_table06"``) and what is compared, with its unit.
    paper, mtcal : float or str
        The paper's printed value and ours (for a Monte Carlo: the posterior-predictive median).
    claim : str
        The paper's statement with its threshold, quoted (or the consistency statement).
    holds : bool or None
        Whether the claim holds in simulation (``None``: nothing tested).
    band : dict or (low, high), optional
        Posterior-predictive spread of the mtcal number: ``metrics.band_or_range`` output
        (``low, high``, optional ``median``, ``n`` draws, ``kind`` in :data:`BAND_KINDS`;
        a dict without ``kind`` is a 95 % band). The row records it as ``"[low, high]"``
        (a range as ``"range [low, high] (n=…)"``), its draws in ``mc_draws``, its kind in
        ``mc_kind`` and whether a numeric paper value lies inside it. A bare pair, or a
        dict without ``n``, has an unknown draw count: :func:`check_bands` (run by
        :func:`comparison_table`) rejects it.
    prior_band : dict or (low, high), optional
        Prior-predictive spread (parameters drawn from the prior): the baseline
        (``prior_band, prior_draws, prior_kind``).
    role : {"train", "heldout", "input", "erratum", "not-compared", "finding"}
        Split role of the paper number (``finding``: our own result).
    source : {"paper claim", "mtcal finding"}
        Whose claim the ``claim`` column states.
    kind : {"claim", "in-sample", "consistency"}, optional
        Default ``"claim"`` when ``holds`` is given and ``source`` is the paper,
        else empty (our own findings are never the paper's claims).
    note : str
        Computed reason a claim fails, or what makes a consistency row true by construction.
    enforce : bool
        Whether :func:`check_claims` enforces the row at the paper's settings
        (False for a claim reported as failing with its reason).
    ref : str
        The split cell(s) compared, ``"file:row:column"`` (``;``-separated).
    """
    if role not in ROLES:
        raise ValueError(f"role must be one of {ROLES}, got {role!r}")
    if source not in SOURCES:
        raise ValueError(f"source must be one of {SOURCES}, got {source!r}")
    if holds is not None and not isinstance(holds, (bool, np.bool_)):
        raise TypeError(f"holds must be bool or None, got {type(holds).__name__}")
    if kind is None:
        kind = "claim" if holds is not None and source == "paper claim" else ""
    elif kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    if kind and holds is None:
        raise ValueError(f"a {kind!r} row needs holds (bool), got None")
    out = {"artifact": artifact, "quantity": quantity, "paper": paper, "mtcal": mtcal,
           "mc_band": "", "paper_in_band": None, "prior_band": "", "prior_in_band": None, "claim": claim,
           "holds": None if holds is None else bool(holds), "kind": kind, "role": role, "source": source,
           "note": note, "enforced": bool(enforce) if holds is not None else None, "ref": ref,
           "mc_low": np.nan, "mc_high": np.nan, "prior_median": np.nan, "prior_low": np.nan, "prior_high": np.nan,
           "mc_draws": None, "mc_kind": "", "prior_draws": None, "prior_kind": ""}
    if band is not None:
        _, low, high, draws, bkind, text = _band(band, "band")
        out.update(mc_band=text, paper_in_band=_inside(paper, low, high), mc_low=low, mc_high=high,
                   mc_draws=draws, mc_kind=bkind)
    if prior_band is not None:
        med, low, high, draws, bkind, text = _band(prior_band, "prior_band")
        out.update(prior_band=text, prior_in_band=_inside(paper, low, high), prior_median=med, prior_low=low,
                   prior_high=high, prior_draws=draws, prior_kind=bkind)
    return out


def claim(artifact: str, quantity: str, paper, mtcal, quote: str, check, *, band=None, prior_band=None,
          role: str = "heldout", enforce: bool = True, note: str = "", ref: str = "", value=None) -> dict:
    """A paper claim tested with its own threshold; the row carries ``check`` so a test can re-run it.

    Parameters
    ----------
    quote : str
        The paper's statement with its threshold, verbatim.
    check : callable
        ``check(value) -> bool``, the claim evaluated on our number; the row's
        ``holds`` is ``check(value)``, ``row["check"]`` is ``check`` and
        ``row["value"]`` the number it was evaluated on (tests perturb it and see
        the check return False).
    value : float, optional
        The number the claim is evaluated on when it is not ``mtcal`` (e.g. a
        97.5 % band end); default ``mtcal``.
    enforce : bool
        False for a claim our model fails (reported with ``note``, the computed reason).

    >>> r = claim("t", "static RMSE (deg)", 0.05, 0.012, "less than 0.05°", lambda v: v < 0.05)
    >>> r["holds"], r["kind"], r["check"](0.06)
    (True, 'claim', False)
    """
    if not callable(check):
        raise TypeError(f"check must be callable, got {type(check).__name__}")
    value = mtcal if value is None else value
    holds = bool(check(value))
    row = comparison_row(artifact, quantity, paper, mtcal, quote, holds, band=band, prior_band=prior_band,
                         role=role, kind="claim", note=note, enforce=enforce, ref=ref)
    row["check"], row["value"] = check, value
    return row


def consistency(artifact: str, quantity: str, paper, mtcal, statement: str, holds: bool, *, by: str,
                band=None, prior_band=None, role: str = "train", ref: str = "", enforce: bool = True) -> dict:
    """A check that holds by construction (never counted as a claim); ``by`` says why it must hold.

    ``enforce=False`` for a fit diagnostic (a statement about a training number the
    approximate fit need not reproduce exactly): reported, never raised.

    >>> r = consistency("t", "b inside prior", 0.2, 0.21, "inside the prior", True, by="the grid lies in the prior")
    >>> r["kind"], r["note"]
    ('consistency', 'the grid lies in the prior')
    """
    if not by:
        raise ValueError("by must say why the check holds by construction")
    return comparison_row(artifact, quantity, paper, mtcal, statement, holds, band=band, prior_band=prior_band,
                          role=role, kind="consistency", note=by, ref=ref, enforce=enforce)


def in_sample(artifact: str, quantity: str, paper, mtcal, statement: str, holds: bool, *, on: str,
              band=None, prior_band=None, role: str = "train", ref: str = "") -> dict:
    """The paper's statement checked on numbers the model was fitted or tuned on (kind ``in-sample``).

    It can fail (a failing one prints "FAILS"), but holding confirms nothing: never counted as a claim,
    never enforced. ``on`` says what was fitted or tuned on the numbers (the row's note, with the
    computed reason when it fails).

    >>> r = in_sample("t", "max error (deg)", 0.05, 0.07, "within 0.05°", False, on="mechanism tuned on Table 9",
    ...               role="tuned")
    >>> r["kind"], r["enforced"], r["role"]
    ('in-sample', False, 'tuned')
    """
    if not on:
        raise ValueError("on must say what was fitted or tuned on the numbers checked")
    if role not in ("train", "tuned"):
        raise ValueError(f"role must be 'train' or 'tuned' for an in-sample check, got {role!r}")
    return comparison_row(artifact, quantity, paper, mtcal, statement, holds, band=band, prior_band=prior_band,
                          role=role, kind="in-sample", note=on, ref=ref, enforce=False)


def comparison_table(rows: list[dict], digits: int = 4) -> pd.DataFrame:
    """Build the comparison table; float cells are rounded to ``digits`` for stable output.

    The band rule is audited here (:func:`check_bands`): a table with a 95 % band from fewer
    than ``metrics.MIN_BAND_DRAWS`` draws, or with a band of unknown draw count, is never built.
    ``mc_draws``/``prior_draws`` are nullable integers (empty where a row has no band).

    >>> from mtcal.core import metrics
    >>> t = comparison_table([comparison_row("a", "x", 1.0, 1.1, "", None, band=metrics.band_or_range([0.9, 1.2]))])
    >>> t.loc[0, "mc_band"], int(t.loc[0, "mc_draws"])
    ('range [0.9, 1.2] (n=2)', 2)
    """
    df = pd.DataFrame(rows, columns=COMPARISON_COLUMNS)
    for col in ("mc_band", "prior_band", "kind", "note", "ref", "mc_kind", "prior_kind"):
        df[col] = df[col].fillna("")
    for col in ("mc_draws", "prior_draws"):
        df[col] = pd.array([None if is_missing(v) else int(v) for v in df[col]], dtype="Int64")
    check_bands(df)

    def fmt(x):
        if isinstance(x, (float, np.floating)):
            return f"{x:.{digits}f}"
        return x
    for col in ("paper", "mtcal"):
        df[col] = df[col].map(fmt)
    return df


def is_missing(v) -> bool:
    """True for an empty cell: None, NaN, pandas NA or an empty/"nan" string (a table read back from CSV).

    >>> [is_missing(v) for v in (None, float("nan"), pd.NA, "", " NaN ", "<NA>", 0, "range")]
    [True, True, True, True, True, True, False, False]
    """
    if v is None or v is pd.NA:
        return True
    if isinstance(v, str):
        return v.strip().lower() in ("", "nan", "<na>", "none")
    try:
        return bool(np.isnan(float(v)))
    except (TypeError, ValueError):
        return False


def draw_count(v) -> int | None:
    """Draw count of a cell (int, float or str from a CSV), or None when unknown (empty, not a whole number >= 1).

    >>> draw_count(1000), draw_count("4.0"), draw_count(np.nan), draw_count("2.5"), draw_count(0)
    (1000, 4, None, None, None)
    """
    if is_missing(v):
        return None
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return int(x) if x.is_integer() and x >= 1 else None


def cell_text(v) -> str:
    """A text cell as ``str``, ``""`` when empty (:func:`is_missing`; a table read back from CSV).

    >>> cell_text("range"), cell_text(None), cell_text(float("nan"))
    ('range', '', '')
    """
    return "" if is_missing(v) else str(v)


def check_bands(table: pd.DataFrame) -> str:
    """Audit the band rule on a comparison table: raise on a row whose band breaks it.

    Every band of a row (``mc_band``: posterior predictive, ``prior_band``: prior predictive;
    :data:`BAND_COUNT_COLUMNS`) must have a known draw count (``mc_draws``/``prior_draws``) and
    a kind in :data:`BAND_KINDS` (a grid ``"credible interval"`` has no draws and needs no count); a
    ``"95 % band"`` must rest on at least
    :data:`mtcal.core.metrics.MIN_BAND_DRAWS` draws (with fewer, the producer reports the
    min–max range with its count: :func:`mtcal.core.metrics.band_or_range`). Run by
    :func:`comparison_table`, :func:`check_claims` and the fidelity scores; works on tables
    read back from CSV (string cells).

    Parameters
    ----------
    table : DataFrame
        A comparison table (:data:`COMPARISON_COLUMNS`; only the band columns are read).

    Returns
    -------
    str
        ``"bands: k 95 % bands (>= 1000 draws), r ranges with their count"``.

    Raises
    ------
    ValueError
        One line naming every offending row (``artifact | quantity``) and what is wrong.

    Examples
    --------
    >>> from mtcal.core import metrics
    >>> rows = [comparison_row("a", "x", 1.0, 1.0, "", None, band=metrics.band_or_range(np.arange(1000.0))),
    ...         comparison_row("b", "y", 1.0, 1.0, "", None, band=metrics.band_or_range([0.5, 1.5]))]
    >>> check_bands(comparison_table(rows))
    'bands: 1 95 % bands (>= 1000 draws), 1 ranges with their count'
    >>> bad = pd.DataFrame([comparison_row("c", "z", 1.0, 1.0, "", None, band=metrics.percentile_band([0.5, 1.5]))])
    >>> check_bands(bad)
    Traceback (most recent call last):
    ...
    ValueError: table must print a 95 % band only from >= 1000 Monte Carlo draws (else the range with its count, metrics.band_or_range); breaking rows: c | z: mc_band is a 95 % band from 2 draws
    """
    from mtcal.core.metrics import MIN_BAND_DRAWS

    if not isinstance(table, pd.DataFrame):
        raise TypeError(f"table must be a pandas DataFrame (a comparison table), got {type(table).__name__}")
    bad, n_band, n_range, n_cred = [], 0, 0, 0
    for i, r in enumerate(table.to_dict("records")):
        name = f"{r.get('artifact', f'row {i}')} | {r.get('quantity', '')}"
        for text_col, draws_col, kind_col in BAND_COUNT_COLUMNS.values():
            if is_missing(r.get(text_col)):
                continue
            draws, kind = draw_count(r.get(draws_col)), cell_text(r.get(kind_col))
            if kind_col not in r or draws_col not in r:
                bad.append(f"{name}: {text_col} has no {draws_col}/{kind_col} columns (a table from before the "
                           "band rule was recorded: regenerate it)")
            elif kind not in BAND_KINDS:
                bad.append(f"{name}: {text_col} has kind {kind!r}, expected one of {BAND_KINDS}")
            elif kind == "credible interval":
                n_cred += 1
            elif draws is None:
                bad.append(f"{name}: {text_col} has no known draw count ({draws_col} empty)")
            elif kind == "95 % band" and draws < MIN_BAND_DRAWS:
                bad.append(f"{name}: {text_col} is a 95 % band from {draws} draws")
            elif kind == "95 % band":
                n_band += 1
            else:
                n_range += 1
    if bad:
        raise ValueError(f"table must print a 95 % band only from >= {MIN_BAND_DRAWS} Monte Carlo draws (else the "
                         "range with its count, metrics.band_or_range); breaking rows: " + "; ".join(bad))
    text = f"bands: {n_band} 95 % bands (>= {MIN_BAND_DRAWS} draws), {n_range} ranges with their count"
    return text + (f", {n_cred} grid credible intervals" if n_cred else "")


def band_description(table: pd.DataFrame, which: str = "mc") -> str:
    """What the bands of a table are: their kind(s) (:data:`BAND_KINDS`) and draw counts.

    Reads the rows of ``table`` with a ``which`` band (``"mc"``: posterior predictive, ``"prior"``:
    prior predictive; :data:`BAND_COUNT_COLUMNS`). One kind: ``"95 % band of 1000 draws"``,
    ``"range of 4 draws"`` (several counts: ``"range of 4–12 draws"``; an unknown count: ``"?"``),
    ``"credible interval"`` (grid, no draws). Several kinds: ``"band (95 % band of 1000 draws;
    range of 4 draws)"`` in the order of :data:`BAND_KINDS` (a row without a kind counts as ``"band"``).
    No band, or a table without the kind column: ``"band"``.

    Raises
    ------
    ValueError
        ``which`` not in :data:`BAND_COUNT_COLUMNS`.

    Examples
    --------
    >>> rows = [comparison_row("a", "x", 1.0, 1.0, "", None, band={"low": 0.9, "high": 1.2, "n": 1000}),
    ...         comparison_row("b", "y", 1.0, 1.0, "", None, band={"low": 0.9, "high": 1.2, "n": 4, "kind": "range"})]
    >>> band_description(comparison_table(rows[:1]))
    '95 % band of 1000 draws'
    >>> band_description(comparison_table(rows))
    'band (95 % band of 1000 draws; range of 4 draws)'
    """
    if which not in BAND_COUNT_COLUMNS:
        raise ValueError(f"which must be one of {tuple(BAND_COUNT_COLUMNS)}, got {which!r}")
    text_col, draws_col, kind_col = BAND_COUNT_COLUMNS[which]
    if kind_col not in table or text_col not in table:
        return "band"
    counts: dict[str, list] = {}
    for r in table.to_dict("records"):
        if not is_missing(r[text_col]):
            counts.setdefault(cell_text(r[kind_col]) or "band", []).append(draw_count(r.get(draws_col)))
    parts = []
    for kind in [k for k in BAND_KINDS if k in counts] + sorted(set(counts) - set(BAND_KINDS)):
        known = sorted({c for c in counts[kind] if c is not None})
        if kind == "credible interval":
            parts.append(kind)
            continue
        n = "?" if None in counts[kind] else f"{known[0]}" if len(known) == 1 else f"{known[0]}–{known[-1]}"
        parts.append(f"{kind} of {n} draw{'' if n == '1' else 's'}")
    if not parts:
        return "band"
    return parts[0] if len(parts) == 1 else f"band ({'; '.join(parts)})"


def band_summary(table: pd.DataFrame) -> str:
    """``"paper value inside the mtcal <bands>: k of n"`` over rows with a band and a numeric paper value.

    ``<bands>`` names the kind(s) and draw counts of those rows' bands (:func:`band_description`).

    >>> t = comparison_table([comparison_row("a", "x", 1.0, 1.1, "", None,
    ...                                      band={"low": 0.9, "high": 1.2, "n": 4, "kind": "range"})])
    >>> band_summary(t)
    'paper value inside the mtcal range of 4 draws: 1 of 1'
    """
    placed = table[table["paper_in_band"].notna()]
    return (f"paper value inside the mtcal {band_description(placed)}: "
            f"{int(placed['paper_in_band'].astype(bool).sum())} of {len(placed)}")


def claims_summary(table: pd.DataFrame) -> str:
    """``"k of n claims hold"`` over the rows of kind ``claim`` (consistency rows are not claims)."""
    tested = table.loc[_kind(table) == "claim", "holds"].dropna()
    return f"{int(tested.astype(bool).sum())} of {len(tested)} claims hold"


def _kind(table: pd.DataFrame) -> pd.Series:
    if "kind" in table:
        return table["kind"].fillna("")
    return pd.Series(np.where(table["holds"].notna(), "claim", ""), index=table.index)


def describe(obj) -> pd.DataFrame:
    """Table of a scenario's fields: name, value, unit, source."""
    rows = []
    for f in fields(obj):
        v = getattr(obj, f.name)
        if hasattr(v, "__dataclass_fields__"):
            continue
        rows.append({"field": f.name, "value": str(v) if not isinstance(v, float) else f"{v:.6g}",
                     "unit": f.metadata.get("unit", ""), "source": f.metadata.get("source", "")})
    return pd.DataFrame(rows)


def band_record(artifact: str, quantity: str, paper_value: float, samples) -> dict:
    """Median and spread of Monte Carlo ``samples`` (1-D, display unit) next to the paper's value.

    The spread follows the band rule (:func:`mtcal.core.metrics.band_or_range`): the 95 % band from
    >= ``MIN_BAND_DRAWS`` samples, else the min–max range. Returns a dict with ``artifact,
    quantity, paper, median, low, high, paper_in_band, n, kind`` (floats, a bool, the draw count
    and the kind); it is also a valid ``band=`` for :func:`comparison_row` (see :func:`band_row`).

    >>> r = band_record("a", "x (deg)", 2.0, [1.0, 2.0, 3.0])
    >>> r["low"], r["high"], r["n"], r["kind"], r["paper_in_band"]
    (1.0, 3.0, 3, 'range', True)
    """
    x = np.asarray(samples, dtype=float)
    if x.ndim != 1 or x.size < 1:
        raise ValueError(f"samples must be a non-empty 1-D array (one value per trial), got shape {x.shape}")
    b = metrics.band_or_range(x)
    med, low, high, pv = float(b["median"]), float(b["low"]), float(b["high"]), float(paper_value)
    return {"artifact": artifact, "quantity": quantity, "paper": pv, "median": med, "low": low, "high": high,
            "paper_in_band": bool(low <= pv <= high), "n": b["n"], "kind": b["kind"]}


def band_row(record: dict, claim: str, holds: bool | None) -> dict:
    """Comparison row from a :func:`band_record`: MC median as the mtcal value, its band (or range) and count."""
    return comparison_row(record["artifact"], record["quantity"], record["paper"], record["median"],
                          claim, holds, band=record)


def band_text(record: dict, digits: int = 4) -> str:
    """``"<quantity>: MC median m [low, high] (paper p)"`` with fixed precision (a range: ``"range [low, high]
    (n=…)"``; :func:`spread_text`).

    >>> band_text(band_record("a", "x (deg)", 2.0, [1.0, 2.0, 3.0]), digits=2)
    'x (deg): MC median 2.00 range [1.00, 3.00] (n=3) (paper 2.00)'
    """
    d = digits
    spread = spread_text(record["low"], record["high"], record.get("kind", "95 % band"), record.get("n"), digits=d)
    return f"{record['quantity']}: MC median {record['median']:.{d}f} {spread} (paper {record['paper']:.{d}f})"


def at_paper_settings(values: dict, defaults: dict) -> bool:
    """True when every parameter in ``values`` equals its paper default in ``defaults``.

    A notebook passes its parameters-cell values and their defaults; the claims are
    then enforced (CI fails on a broken reproduction) only at the paper's settings,
    and merely reported in a what-if run. Run size (``SIZE``, trial counts) and the
    RNG seed are not scenario parameters and should not be passed.

    >>> at_paper_settings({"gyro_grade": "wang2023cja"}, {"gyro_grade": "wang2023cja"})
    True
    >>> at_paper_settings({"gyro_grade": "industrial"}, {"gyro_grade": "wang2023cja"})
    False
    """
    merge_parameters(values, defaults)  # rejects names not in defaults

    def same(a, b):
        try:
            return bool(np.all(np.asarray(a) == np.asarray(b))) and np.shape(a) == np.shape(b)
        except (TypeError, ValueError):
            return a == b
    return all(same(values[k], defaults[k]) for k in values)


def check_claims(table: pd.DataFrame, *, enforce: bool) -> str:
    """Evaluate every tested row of a comparison table; fail only when ``enforce``.

    Parameters
    ----------
    table : DataFrame
        Output of :func:`comparison_table`.
    enforce : bool
        True at the paper's settings: raise ``AssertionError`` listing each
        enforced row (``enforced`` True: claims we assert, consistency checks)
        that does not hold, so CI fails when a reproduction breaks. Claims
        reported as failing (``enforced`` False) are listed, never raised.
        False in a what-if run: never raise, return the report.
        The band rule (:func:`check_bands`) is audited in both cases (a band from
        too few draws is a reporting error, not a what-if result).

    Returns
    -------
    str
        ``"k of n claims hold"`` (kind ``claim``), one line per failing claim with
        its computed reason, and the consistency count when there are any.

    >>> t = comparison_table([comparison_row("a", "x", 1.0, 1.0, "x = 1", True),
    ...                       comparison_row("b", "y", 1.0, 2.0, "y = 1", False, note="y is 2")])
    >>> print(check_claims(t, enforce=False))
    1 of 2 claims hold; not holding:
      b | y | y = 1 | paper 1.0000 | mtcal 2.0000 | y is 2
    """
    check_bands(table)
    kind = _kind(table)
    tested = table[table["holds"].notna() & (kind == "claim")]
    failing = tested[~tested["holds"].astype(bool)]
    text = f"{len(tested) - len(failing)} of {len(tested)} claims hold"
    if len(failing):
        text += "; not holding:\n" + "\n".join(
            f"  {r.artifact} | {r.quantity} | {r.claim} | paper {r.paper} | mtcal {r.mtcal}"
            + (f" | {r.note}" if getattr(r, "note", "") else "") for r in failing.itertuples())
    for k, title in (("in-sample", "in-sample checks (on numbers the model was fitted or tuned on; not claims)"),
                     ("consistency", "consistency checks (true by construction, not claims)")):
        rows = table[table["holds"].notna() & (kind == k)]
        if len(rows):
            n_ok = int(rows["holds"].astype(bool).sum())
            text += f"\n{title}: {n_ok} of {len(rows)} hold"
            bad = rows[~rows["holds"].astype(bool)]
            text += "".join(f"\n  FAILS: {r.artifact} | {r.quantity} | {r.claim} | mtcal {r.mtcal} | {r.note}"
                            for r in bad.itertuples())
    own = table[table["holds"].notna() & (kind == "")]
    if len(own):
        n_ok = int(own["holds"].astype(bool).sum())
        text += f"\nour own findings: {n_ok} of {len(own)} hold"
    checked = table[table["holds"].notna()]
    if "enforced" in checked:
        enforced = checked["enforced"].fillna(True).astype(bool)
    else:
        enforced = pd.Series(True, index=checked.index)
    broken = checked[enforced & ~checked["holds"].astype(bool)]
    if enforce and len(broken):
        raise AssertionError("at the paper's settings every enforced claim and consistency check must hold; "
                             + "; ".join(f"{r.artifact} | {r.quantity}" for r in broken.itertuples()))
    return text


def role_summary(table: pd.DataFrame) -> str:
    """Paper-inside-band counts split by role (``heldout`` rows are the out-of-sample test).

    The text names the kind(s) and draw counts of the bands counted (:func:`band_description`).

    >>> t = comparison_table([comparison_row("a", "x", 1.0, 1.1, "", None, band={"low": 0.9, "high": 1.2, "n": 5,
    ...                                                                           "kind": "range"}),
    ...                       comparison_row("b", "y", 1.0, 1.1, "", None, band={"low": 1.05, "high": 1.2, "n": 1000},
    ...                                      role="train")])
    >>> role_summary(t)
    'paper inside our band (95 % band of 1000 draws; range of 5 draws): train 0 of 1, heldout 1 of 1'
    >>> role_summary(t[t.role == "train"])
    'paper inside our 95 % band of 1000 draws: train 0 of 1'
    """
    placed = table[table["paper_in_band"].notna()]
    parts = []
    for role in ROLES:
        rows = placed[placed["role"] == role]
        if len(rows):
            parts.append(f"{role} {int(rows['paper_in_band'].astype(bool).sum())} of {len(rows)}")
    return f"paper inside our {band_description(placed)}: " + (", ".join(parts) if parts else "no banded rows")


#: Former name of :func:`role_summary` (kept for the notebooks that call it).
prediction_summary = role_summary


def implied_by_training(statement, training) -> dict:
    """How far the training statements imply a tested one, per prior-predictive draw (:data:`IMPLIED_MIN`).

    Parameters
    ----------
    statement : array_like of bool, shape (n,)
        The tested statement in each draw.
    training : array_like of bool, shape (n,)
        Every training statement holds in the draw.

    Returns
    -------
    dict
        ``p_given`` P(statement | training holds) and ``n_given`` its draws, ``p_else`` / ``n_else`` the same
        where a training statement fails (NaN without draws), ``implied`` ``p_given >= IMPLIED_MIN`` (False
        without a draw where the training holds: nothing to condition on), ``text`` the fraction with its
        Wilson 95 % interval (near :data:`IMPLIED_MIN` another seed may flip the label: the interval says how near).

    Examples
    --------
    >>> r = implied_by_training([True, True, False, True], [True, True, False, False])
    >>> r["p_given"], r["n_given"], r["p_else"], r["implied"], r["text"]
    (1.0, 2, 0.5, True, '100.0 % (Wilson 95 % 34.2–100.0 %)')
    """
    from mtcal.reporting.binomial import wilson_interval

    statement, training = np.asarray(statement, bool), np.asarray(training, bool)
    n_given, n_else = int(training.sum()), int((~training).sum())
    k = int(statement[training].sum())
    p_given = k / n_given if n_given else float("nan")
    p_else = float(statement[~training].mean()) if n_else else float("nan")
    lo, hi = wilson_interval(k, n_given) if n_given else (float("nan"), float("nan"))
    return {"p_given": p_given, "n_given": n_given, "p_else": p_else, "n_else": n_else,
            "implied": bool(n_given and p_given >= IMPLIED_MIN),
            "text": f"{100 * p_given:.1f} % (Wilson 95 % {100 * lo:.1f}–{100 * hi:.1f} %)"}
