"""core.artifacts: the one producer return type and its identification decorator."""

import pandas as pd
import pytest

from mtcal.core.artifacts import Artifact, produces


def test_defaults_are_independent_and_positional_order_is_table_rows_data_lines():
    a, b = Artifact(), Artifact()
    a.rows.append({"holds": True})
    assert b.rows == [] and b.data == {} and b.lines == []
    t = pd.DataFrame({"x": [1.0]})
    c = Artifact(t, [{"r": 1}], {"d": 2}, ["l"])
    assert c.table is t and c.rows == [{"r": 1}] and c.data == {"d": 2} and c.lines == ["l"]


def test_produces_stamps_without_overriding_the_producer():
    @produces("demo_table02", "table", "Table 2")
    def table02(given=""):
        return Artifact(artifact_id=given)

    a = table02()
    assert (a.artifact_id, a.kind, a.paper_item) == ("demo_table02", "table", "Table 2")
    assert a.producer.endswith("table02") and table02.artifact_id == "demo_table02"
    assert table02("other").artifact_id == "other"


def test_errors():
    with pytest.raises(ValueError, match="kind must be one of"):
        Artifact(kind="plot")
    with pytest.raises(ValueError, match="kind must be one of"):
        produces("x", "")
