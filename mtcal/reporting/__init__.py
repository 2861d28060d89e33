"""Reporting: the papers' numbers, paper-vs-mtcal comparison with Monte Carlo bands, output files,
notebook runs (what-if runs and their comparison).

The public names of every submodule are re-exported here (see ``__all__``).
"""

from . import paper_numbers, compare, output, runs
from .paper_numbers import *  # noqa: F401,F403
from .compare import *  # noqa: F401,F403
from .output import *  # noqa: F401,F403
from .runs import *  # noqa: F401,F403
import sys as _sys  # noqa: E402

# the submodules, not same-named functions (e.g. filters.qncf the module, filters.qncf.qncf the function)
paper_numbers, compare, output, runs = (_sys.modules[f"{__name__}.{_n}"]
                                        for _n in ('paper_numbers', 'compare', 'output', 'runs'))

__all__ = ["paper_numbers", "compare", "output", "runs"]
__all__ += [n for m in (paper_numbers, compare, output, runs) for n in m.__all__ if n not in __all__]
