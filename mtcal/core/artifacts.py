"""The one return type of every study's artifact producer.

A producer (``mtcal.studies.<paper>.artifacts.<fn>``) computes the numbers of
one paper table or figure (or one of mtcal's ``extra`` artifacts) and returns an
:class:`Artifact`: the table to save (``data/<id>.csv``), the arrays a plot
function draws (``mtcal.studies.<paper>.plots``), the paper-vs-mtcal comparison
rows (:func:`mtcal.reporting.compare.comparison_row`) and a few summary lines
for the notebook to print. Angles in a table or in ``data`` are in degrees
(display edge); everything upstream is SI.

Identification fields (``artifact_id``, ``kind``, ``paper_item``, ``producer``)
are optional: a producer fills them when it knows them; the notebooks name
their outputs with the artifact ID. See ``docs/study_template.md``.

Examples
--------
>>> import pandas as pd
>>> a = Artifact(pd.DataFrame({"x": [1.0]}), rows=[{"holds": True}], lines=["x = 1"],
...              artifact_id="demo_table01", kind="table", paper_item="Table 1")
>>> a.kind, len(a.rows), a.lines[0]
('table', 1, 'x = 1')
>>> @produces("demo_fig01", "figure", "Fig. 1")
... def fig01():
...     return Artifact(lines=["ok"])
>>> a = fig01()
>>> a.artifact_id, a.kind, a.paper_item, a.producer.endswith("fig01")
('demo_fig01', 'figure', 'Fig. 1', True)
>>> Artifact(kind="chart")
Traceback (most recent call last):
...
ValueError: kind must be one of ['', 'figure', 'table'], got 'chart'
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

__all__ = ["Artifact", "ARTIFACT_KINDS", "produces"]

#: Allowed values of :attr:`Artifact.kind` (``""`` = not stated by the producer).
ARTIFACT_KINDS = ("", "figure", "table")


@dataclass
class Artifact:
    """What an artifact producer returns.

    Parameters
    ----------
    table : pandas.DataFrame or None
        The artifact's table (saved as ``data/<artifact_id>.csv``); angles in degrees.
    rows : list of dict
        Comparison rows (:func:`mtcal.reporting.compare.comparison_row`), each with
        ``role`` (the split role train / heldout / input / erratum / not-compared, or finding), ``kind``
        (claim / consistency) and ``source``.
    data : dict
        Arrays, results and labels for the study's plot functions (degrees).
    lines : list of str
        Summary lines for the notebook to print (fixed precision).
    artifact_id : str
        ``<paper key>_figNN`` / ``<paper key>_tableNN`` / ``<paper key>_extra_<slug>``.
    kind : {"", "figure", "table"}
        What the notebook saves.
    paper_item : str
        The paper's item (``"Fig. 6"``, ``"Table 5"``) or ``""`` for an mtcal extra.
    producer : str
        Dotted name of the producing function.

    References
    ----------
    ``docs/study_template.md`` (one study template; artifact naming).
    """

    table: object = None
    rows: list = field(default_factory=list)
    data: dict = field(default_factory=dict)
    lines: list = field(default_factory=list)
    artifact_id: str = ""
    kind: str = ""
    paper_item: str = ""
    producer: str = ""

    def __post_init__(self) -> None:
        if self.kind not in ARTIFACT_KINDS:
            raise ValueError(f"kind must be one of {list(ARTIFACT_KINDS)}, got {self.kind!r}")


def produces(artifact_id: str, kind: str, paper_item: str = ""):
    """Decorator of an artifact producer: stamps the returned :class:`Artifact` with its ID, kind,
    paper item and the producer's dotted name (values the producer left empty).

    Parameters
    ----------
    artifact_id : str
        ``<paper key>_figNN`` / ``_tableNN`` / ``_extra_<slug>``.
    kind : {"figure", "table"}
        The artifact's main output.
    paper_item : str
        ``"Fig. 6"``, ``"Table 5"``; ``""`` for an mtcal extra.
    """
    if kind not in ARTIFACT_KINDS[1:]:
        raise ValueError(f"kind must be one of {list(ARTIFACT_KINDS[1:])}, got {kind!r}")

    def wrap(fn):
        name = f"{fn.__module__}.{fn.__qualname__}"

        @functools.wraps(fn)
        def producer(*args, **kwargs):
            art = fn(*args, **kwargs)
            art.artifact_id = art.artifact_id or artifact_id
            art.kind = art.kind or kind
            art.paper_item = art.paper_item or paper_item
            art.producer = art.producer or name
            return art

        producer.artifact_id = artifact_id
        return producer
    return wrap
