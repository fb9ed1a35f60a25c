# ruff: noqa: INP001, E501
"""cap_nearest.py SPEC...: the part lookups' nearest-example calls of at least 5,000 rows in the photo stages of
captured specs (capture.py), with their answers, saved for kab.py (/tmp/s38photo/nearest_calls.pt)."""

import pickle
import sys

import torch

from sdn3d.editing.photo import transfer

torch.set_num_threads(1)
nearest_examples = transfer.nearest_examples
calls = []


def recorded(query: torch.Tensor, examples: torch.Tensor, k: int, shared_from: int | None = None) -> torch.Tensor:
    found = nearest_examples(query, examples, k, shared_from)
    if len(query) >= 5000:
        calls.append((query.clone(), examples.clone(), k, shared_from, found.clone()))
    return found


transfer.nearest_examples = recorded
for spec in sys.argv[1:]:
    with open(f"/tmp/s38photo/cap/{spec}.pkl", "rb") as fh:
        a = pickle.load(fh)
    src = transfer.PhotoSource(a["original"], a["frame"], a["scene"], a["bank"], a["settings"])
    transfer.render_photo(a["original"], a["frame"], a["scene"], a["edited"], a["bank"], a["settings"],
                          a["recolor"], None, source=src)
torch.save(calls, "/tmp/s38photo/nearest_calls.pt")
print([(len(c[0]), len(c[1]), c[2]) for c in calls])
