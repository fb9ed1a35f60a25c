# ruff: noqa: E402
"""What the unseen sides' nearest-example search (transfer._nearest_examples) is asked, and what an exact float64
k-d tree (scipy's cKDTree) would answer: wraps the function, then runs a script (its arguments follow: session 14's
draw_edits.py or session 23's editor/editor_turns.py). For every call it prints the query count Q, example count E
and k, the CPU ms of the float32 cdist + topk (the code's) and of the k-d tree, and how many query rows' index lists
differ (order included). Run from the repository root with PYTHONPATH=CODE/src:

    python nearest_probe.py SCRIPT [SCRIPT ARGS...] > probe.txt
"""

import runpy
import sys
import time

import torch
from scipy.spatial import cKDTree

import sdn3d.editing.photo.transfer as transfer

rows = []
original = transfer._nearest_examples


def probed(query, examples, k):
    t0 = time.process_time()
    got = original(query, examples, k)
    t1 = time.process_time()
    kk = min(k, len(examples))
    _, idx = cKDTree(examples.double().numpy()).query(query.double().numpy(), k=kk)
    tree = torch.from_numpy(idx.reshape(len(query), kk))
    t2 = time.process_time()
    differ = int((tree != got).any(1).sum())
    rows.append((len(query), len(examples), k, 1e3 * (t1 - t0), 1e3 * (t2 - t1), differ))
    print(f"nearest Q {len(query)} E {len(examples)} k {k}: cdist+topk {1e3 * (t1 - t0):.1f} ms, "
          f"k-d tree {1e3 * (t2 - t1):.1f} ms, rows differing {differ}", file=sys.stderr)
    return got


transfer._nearest_examples = probed
script, sys.argv = sys.argv[1], sys.argv[1:]
try:
    runpy.run_path(script, run_name="__main__")
finally:
    q = sum(r[0] for r in rows)
    print(f"TOTAL calls {len(rows)} queries {q} cdist+topk {sum(r[3] for r in rows):.0f} ms "
          f"k-d tree {sum(r[4] for r in rows):.0f} ms rows differing {sum(r[5] for r in rows)}", file=sys.stderr)
