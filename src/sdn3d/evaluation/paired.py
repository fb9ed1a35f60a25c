"""Paired comparisons of two methods over the same benchmark entries: the mean difference with a paired bootstrap
interval, and win counts (who won, said with the evidence a reader needs to weigh it).

Every table that sets 3D-SDN beside a baseline reports these: with a handful of entries a gap in the means is an
anecdote, and the interval of the paired difference (resampling whole entries, so both methods keep their pairing)
says whether it is more.

>>> d = paired_difference([12.0, 13.0, 15.0, 14.0] * 3, [11.0, 12.5, 14.0, 14.0] * 3, higher_is_better=True)
>>> (d.n, d.wins, d.losses, d.ties, round(d.mean, 3))
(12, 9, 0, 3, 0.625)
>>> d.verdict
'better'
>>> paired_difference([1.0, 2.0], [2.0, 3.0], higher_is_better=True).verdict
'too few entries'

Entries of one car (the benchmark edits a car from several source frames and in every variation of its world) are not
several pieces of evidence: with ``groups``, the bootstrap resamples whole groups (a cluster bootstrap of the entries'
mean) and the verdict needs :data:`MIN_ENTRIES` distinct groups.

>>> g = paired_difference([12.0, 13.0, 13.0], [11.0, 12.0, 12.0], higher_is_better=True, groups=["a", "b", "b"])
>>> (g.n, g.groups, g.mean)
(3, 2, 1.0)
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["PairedDifference", "paired_difference", "compare_entries", "BOOTSTRAP_SAMPLES", "LOWER_IS_BETTER",
           "MIN_ENTRIES"]

BOOTSTRAP_SAMPLES = 4000
#: Fewer paired entries give no verdict: a percentile bootstrap of a handful of values is far too narrow.
MIN_ENTRIES = 10
LOWER_IS_BETTER = frozenset({"l1", "lpips"})


@dataclass(frozen=True)
class PairedDifference:
    """``ours - theirs`` over ``n`` paired entries: its mean, the bootstrap interval ``[low, high]`` at ``level``,
    and how many entries each side won (by the metric's own direction; a tie is an exactly equal value).
    ``groups``: how many distinct groups the entries form when they were resampled by group (None: each entry its
    own)."""

    n: int
    mean: float
    low: float
    high: float
    wins: int
    losses: int
    ties: int
    higher_is_better: bool
    level: float = 0.95
    groups: int | None = None

    @property
    def verdict(self) -> str:
        """``'better'`` / ``'worse'`` when the interval excludes 0 (for ours), else ``'no clear difference'``;
        ``'too few entries'`` under :data:`MIN_ENTRIES` entries (distinct groups, where grouped)."""
        if self.n == 0:
            return "no entries"
        if (self.n if self.groups is None else self.groups) < MIN_ENTRIES:
            return "too few entries"
        if self.low > 0 or self.high < 0:
            ahead = (self.low > 0) == self.higher_is_better
            return "better" if ahead else "worse"
        return "no clear difference"

    def to_dict(self) -> dict:
        return {"n": self.n, "mean": self.mean, "low": self.low, "high": self.high, "wins": self.wins,
                "losses": self.losses, "ties": self.ties, "higher_is_better": self.higher_is_better,
                "level": self.level, "groups": self.groups, "verdict": self.verdict}


def paired_difference(ours: Sequence[float], theirs: Sequence[float], higher_is_better: bool,
                      samples: int = BOOTSTRAP_SAMPLES, level: float = 0.95, seed: int = 0,
                      groups: Sequence[Hashable] | None = None) -> PairedDifference:
    """Paired bootstrap of ``mean(ours - theirs)``: ``samples`` resamplings of whole entries (seeded: the same
    values give the same interval). ``ours`` and ``theirs`` are ``(N,)``, entry ``i`` of both the same entry.
    ``groups`` ``(N,)``: a label per entry; entries of one label are resampled together (module doc). Where every
    label is distinct the result is the ungrouped one, draw for draw."""
    a = np.asarray(ours, dtype=np.float64)
    b = np.asarray(theirs, dtype=np.float64)
    if a.shape != b.shape or a.ndim != 1:
        raise ValueError(f"paired values must be two (N,) sequences of one length, got {a.shape} and {b.shape}")
    if groups is not None and len(groups) != a.size:
        raise ValueError(f"groups must give one label per entry: {len(groups)} labels for {a.size} entries")
    d = a - b
    n = int(d.size)
    if n == 0:
        return PairedDifference(0, float("nan"), float("nan"), float("nan"), 0, 0, 0, higher_is_better, level)
    rng = np.random.default_rng(seed)
    first: dict[Hashable, int] = {}  # labels numbered by first appearance: the same draws in every process
    labels = None if groups is None else np.asarray([first.setdefault(g, len(first)) for g in groups])
    k = None if labels is None else len(first)
    if k is None or k == n:
        means = d[rng.integers(0, n, size=(samples, n))].mean(axis=1)
    else:  # resample whole groups: each draw's mean over the entries of the groups it drew
        sums, sizes = np.bincount(labels, weights=d, minlength=k), np.bincount(labels, minlength=k)
        drawn = rng.integers(0, k, size=(samples, k))
        means = sums[drawn].sum(axis=1) / sizes[drawn].sum(axis=1)
    low, high = np.quantile(means, [(1 - level) / 2, (1 + level) / 2])
    ahead = d > 0 if higher_is_better else d < 0
    behind = d < 0 if higher_is_better else d > 0
    return PairedDifference(n, float(d.mean()), float(low), float(high), int(ahead.sum()), int(behind.sum()),
                            int((d == 0).sum()), higher_is_better, level, k)


def compare_entries(entries: Sequence[Mapping], mode: str, ours: str, theirs: str,
                    columns: Sequence[tuple[str, str]], group_of: Callable[[Mapping], Hashable] | None = None
                    ) -> dict[tuple[str, str], PairedDifference]:
    """``{(metric, region): ours - theirs}`` over the benchmark entries (``results.json``'s per-entry records:
    ``entry['metrics'][mode][method][region][metric]``) where both methods have a finite value. ``group_of``: the
    group of an entry record (entries of one group resampled together: :func:`paired_difference`)."""
    out = {}
    for metric, region in columns:
        a, b, g = [], [], []
        for entry in entries:
            methods = (entry.get("metrics") or {}).get(mode) or {}
            x = (methods.get(ours) or {}).get(region, {}).get(metric)
            y = (methods.get(theirs) or {}).get(region, {}).get(metric)
            if isinstance(x, (int, float)) and isinstance(y, (int, float)) and np.isfinite(x) and np.isfinite(y):
                a.append(float(x))
                b.append(float(y))
                g.append(None if group_of is None else group_of(entry))
        out[(metric, region)] = paired_difference(a, b, higher_is_better=metric not in LOWER_IS_BETTER,
                                                  groups=None if group_of is None else g)
    return out
