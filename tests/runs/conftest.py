"""A tiny notebook (py:percent) for run tests: a parameters cell, a table, a comparison table."""

import pytest

TINY = '''# %% [markdown]
# # 99 — tiny test notebook

# %% tags=["parameters"]
SIZE = None  # "ci" or "full"
SEED = 1
gain = 2.0  # scale of y
label = "base"
FAIL = False

# %%
import pandas as pd
from mtcal.reporting import compare, output

SIZE = output.run_size(SIZE)

# %% [markdown]
# ## tiny_table — y = gain · x

# %%
df = pd.DataFrame({"x": [1.0, 2.0], "y": [gain * 1.0, gain * 2.0], "label": [label, label]})
output.save_table(df, "tiny_table")
print(f"size={SIZE} gain={gain} label={label}")

# %%
assert not FAIL, "asked to fail"
rows = [compare.comparison_row("tiny_table", "y at x=2", 4.0, gain * 2.0, "y(2) = 4", gain * 2.0 == 4.0),
        compare.comparison_row("tiny_table", "x count", 2, 2, "two points", True)]
output.save_table(compare.comparison_table(rows), "tiny_comparison")
'''


@pytest.fixture
def tiny_notebooks(tmp_path):
    folder = tmp_path / "notebooks"
    folder.mkdir()
    (folder / "99_tiny.py").write_text(TINY, encoding="utf-8")
    return folder
