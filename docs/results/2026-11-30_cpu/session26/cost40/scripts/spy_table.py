"""Inclusive shares of named stages in a py-spy ``--threads -f raw`` recording of one call: ``spy_table.py RAW RATE``.

A sample counts for a stage where a frame of its stack contains the stage's pattern (first match in STAGES order
wins for the "exclusive" column; the inclusive column counts every stage on the stack). Seconds = samples / RATE,
summed over threads (so the fit's two threads count twice where they run at once).
"""

from __future__ import annotations

import sys
from collections import Counter

#: (label, substring of a frame), outermost stages last so the first match is the most specific.
STAGES = [
    ("soft raster kernel (native)", "_call (sdn3d/render/soft.py"),
    ("soft raster (other)", "sdn3d/render/soft.py"),
    ("hard rasterizer", "sdn3d/render/rasterize.py"),
    ("autograd backward", "run_backward"),
    ("fit: adam_fit (other)", "adam_fit"),
    ("fit (other)", "geometric/fit.py"),
    ("box masks GrabCut", "box_masks"),
    ("box objects (other)", "box_objects"),
    ("semantic branch", "semantic/predict"),
    ("geometric branch net", "geometric/predict"),
    ("derender (other)", "derender.py"),
    ("photo path", "editing/photo"),
    ("edit (other)", "session.py"),
    ("hydra compose", "compose_config"),
    ("load models", "load_models"),
    ("write outputs", "_write_outputs"),
    ("import torch", "<module> (torch/__init__.py"),
    ("import (other)", "_find_and_load"),
]


def main() -> None:
    path, rate = sys.argv[1], float(sys.argv[2])
    exclusive: Counter[str] = Counter()
    inclusive: Counter[str] = Counter()
    threads: Counter[str] = Counter()
    total = 0
    for line in open(path):
        stack, _, count = line.rstrip("\n").rpartition(" ")
        n = int(count)
        total += n
        frames = stack.split(";")
        threads[frames[0]] += n
        seen = [label for label, pat in STAGES if any(pat in f for f in frames)]
        exclusive[seen[0] if seen else "other"] += n
        for label in seen:
            inclusive[label] += n
    print(f"samples {total} = {total / rate:.2f} thread-s at {rate:g} Hz")
    for t, n in threads.most_common():
        print(f"  thread {t}: {n / rate:.2f} s")
    print("| stage | exclusive s | inclusive s |\n|---|---|---|")
    for label, _ in STAGES + [("other", "")]:
        if exclusive[label] or inclusive[label]:
            print(f"| {label} | {exclusive[label] / rate:.2f} | {inclusive[label] / rate:.2f} |")


if __name__ == "__main__":
    main()
