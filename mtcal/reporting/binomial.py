"""Binomial proportions: the Wilson score interval and the one coin-flip rule of the suite.

A statement decided by a share of Monte Carlo trials (a bake-off ranking by its paired wins, a
wang2023cja claim judged on its median trial) is a verdict only when that share differs from ½
beyond Monte Carlo error. The suite has one rule for it, :func:`coin_flip`: the share of ``wins``
in ``n`` trials is **resolved** when ½ lies outside its Wilson score 95 % interval
(:func:`wilson_interval`). The Wilson interval is the standard interval of a binomial proportion
(Agresti & Coull 1998): its coverage stays near nominal at small ``n`` and near 0 or 1, where
the Wald interval ``p ± 2·√(p(1 − p)/n)`` (and the "two standard errors of ½" rule
``|p − ½| > 2·√(0.25/n)``) is too narrow or degenerate.

References
----------
Wilson E. B., "Probable inference, the law of succession, and statistical inference",
J. Am. Stat. Assoc. 1927, 22(158):209–212.
Agresti A., Coull B. A., "Approximate is better than 'exact' for interval estimation of binomial
proportions", Am. Stat. 1998, 52(2):119–126.

Examples
--------
>>> coin_flip(7, 12).verdict
'not resolved: wins 7 of 12 paired trials (Wilson 95 % 0.32–0.81 includes ½)'
>>> coin_flip(10, 12).resolved
True
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["wilson_interval", "coin_flip", "CoinFlip"]


def wilson_interval(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion ``k / n``.

    Parameters
    ----------
    k, n : int
        Successes and trials, ``0 <= k <= n``, ``n >= 1`` (``bool`` is not a count).
    level : float
        Confidence level in (0, 1).

    Returns
    -------
    (low, high) : tuple of float
        Bounds in [0, 1].

    Raises
    ------
    TypeError
        ``k`` or ``n`` not an int.
    ValueError
        ``n < 1``, ``k`` outside ``[0, n]`` or ``level`` outside (0, 1).

    References
    ----------
    Wilson 1927 (see module references).

    Examples
    --------
    >>> [round(v, 4) for v in wilson_interval(8, 10)]
    [0.4902, 0.9433]
    """
    from scipy.stats import norm

    ints = [isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_)) for v in (k, n)]
    if not all(ints):
        raise TypeError(f"k and n must be int, got {type(k).__name__}, {type(n).__name__}")
    if n < 1 or not 0 <= k <= n:
        raise ValueError(f"need n >= 1 and 0 <= k <= n, got k={k}, n={n}")
    if not 0 < level < 1:
        raise ValueError(f"level must be in (0, 1), got {level}")
    z = float(norm.ppf(0.5 + level / 2))
    p = k / n
    den = 1 + z * z / n
    mid = (p + z * z / (2 * n)) / den
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return float(max(0.0, mid - half)), float(min(1.0, mid + half))


class CoinFlip(NamedTuple):
    """The answer of :func:`coin_flip`: the Wilson 95 % interval of ``wins / n``, and whether ½ is outside it.

    Attributes
    ----------
    low, high : float
        Wilson score 95 % interval of the share of wins.
    resolved : bool
        ½ lies outside ``[low, high]``: the share differs from a coin flip beyond Monte Carlo
        error (above ½ when ``low > 0.5``, below when ``high < 0.5``).
    verdict : str
        One line: ``"resolved: wins 10 of 12 paired trials (Wilson 95 % 0.55–0.95)"``;
        ``"… below ½)"`` when the interval lies below ½; ``"not resolved: … includes ½)"``.
    """

    low: float
    high: float
    resolved: bool
    verdict: str


def coin_flip(wins: int, n: int, *, counted: str = "wins", of: str = "paired trials") -> CoinFlip:
    """Whether ``wins`` of ``n`` trials differ from a coin flip: ½ outside the Wilson 95 % interval.

    The one rule of the suite for a verdict decided by a share of Monte Carlo trials (module
    docstring; ``docs/conventions.md``, "Coin flips are not verdicts").

    Parameters
    ----------
    wins, n : int
        Trials in which the statement holds, and trials; ``n >= 1``, ``0 <= wins <= n``.
    counted, of : str
        Words of the verdict: ``"<counted> <wins> of <n> <of>"`` (default
        ``"wins 7 of 12 paired trials"``; a claim: ``counted="holds in", of="trials"``).

    Returns
    -------
    CoinFlip
        ``(low, high, resolved, verdict)``.

    Raises
    ------
    TypeError
        ``wins`` or ``n`` not an int (a share must be given as its count).
    ValueError
        ``n < 1`` or ``wins`` outside ``[0, n]``.

    Examples
    --------
    >>> c = coin_flip(7, 12)
    >>> round(c.low, 2), round(c.high, 2), c.resolved
    (0.32, 0.81, False)
    >>> c.verdict
    'not resolved: wins 7 of 12 paired trials (Wilson 95 % 0.32–0.81 includes ½)'
    >>> coin_flip(863, 1000).verdict
    'resolved: wins 863 of 1000 paired trials (Wilson 95 % 0.84–0.88)'
    >>> coin_flip(2, 12, counted="holds in", of="trials").verdict
    'resolved: holds in 2 of 12 trials (Wilson 95 % 0.05–0.45 below ½)'
    """
    low, high = wilson_interval(wins, n)
    resolved = bool(low > 0.5 or high < 0.5)
    tail = "" if low > 0.5 else " below ½" if high < 0.5 else " includes ½"
    what = "resolved" if resolved else "not resolved"
    return CoinFlip(low, high, resolved,
                    f"{what}: {counted} {int(wins)} of {int(n)} {of} (Wilson 95 % {low:.2f}–{high:.2f}{tail})")
