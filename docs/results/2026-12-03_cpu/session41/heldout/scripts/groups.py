# ruff: noqa: INP001
"""The car-group bootstrap that arms.py and kinds.py share: entries that edit the same cars are one group, resampled
together (as sdn3d-bench's "Who won"; 4000 draws)."""
import numpy as np


def group_key(record):
    """The group of a results.json entry record: its cars, else the entry itself."""
    return tuple(sorted(record["cars"])) or ("entry", record["index"])


def group_mean(groups, rng):
    """``(mean, 2.5 %, 97.5 %)`` over the entries of ``groups`` ({key: [values]}), the interval by resampling groups."""
    sums = np.array([sum(v) for v in groups.values()])
    counts = np.array([len(v) for v in groups.values()])
    draws = rng.integers(0, len(sums), (4000, len(sums)))
    boot = sums[draws].sum(1) / counts[draws].sum(1)
    return sums.sum() / counts.sum(), np.percentile(boot, 2.5), np.percentile(boot, 97.5)
