"""Time per box object for mask and fit: the real frame's two cars listed by `sdn3d-edit` calls in one process.

    .venv/bin/python docs/results/2026-11-26_cpu/issue31_s3/mask_fit_timing.py RUN [CALLS]

The first call is a fresh process's (cold); the later ones find PyTorch warm (the editor's case). For each call:
GrabCut (the first masks), the 3D fit, the second GrabCut seeded by the fitted shapes, and the whole de-render
(with the geometric branch and the texture codes), in ms, and per object ((GrabCut + fit + second GrabCut) / 2).
The three stages are timed by wrapping the library functions the de-render calls; nothing else changes.
"""

import json
import sys
import tempfile
import time
from pathlib import Path

import sdn3d.box_masks as box_masks
import sdn3d.geometric.fit as fit
from sdn3d.cli.edit import main as edit

REPO = Path(__file__).resolve().parents[4]
IMAGE = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
spent: dict[str, float] = {}


def timed(module, name: str, label: str) -> None:
    inner = getattr(module, name)

    def wrapper(*args, **kwargs):
        start = time.perf_counter()
        try:
            return inner(*args, **kwargs)
        finally:
            spent[label] = spent.get(label, 0.0) + 1000 * (time.perf_counter() - start)

    setattr(module, name, wrapper)


def run() -> None:
    timed(box_masks, "grabcut_masks", "grabcut_ms")
    timed(fit, "fit_to_masks", "fit_ms")
    timed(box_masks, "refine_with_silhouettes", "second_grabcut_ms")
    calls = int(sys.argv[2]) if len(sys.argv) > 2 else 4
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        spec = Path(tmp) / "spec.yaml"
        spec.write_text("objects:\n  - {box: [466, 203, 666, 333], class: Car}\n"
                        "  - {box: [704, 194, 917, 305], class: Car}\n")
        for call in range(calls):
            spent.clear()
            out = Path(tmp) / f"o{call}"
            assert edit([f"input.image={IMAGE}", f"run={sys.argv[1]}", f"edits={spec}", "proposals=boxes",
                         f"output_dir={out}", "threads=2"]) == 0
            row = {k: round(v) for k, v in spent.items()}
            row["derender_ms"] = round(json.loads((out / "edit.json").read_text())["timings_ms"]["derender_ms"])
            row["mask_and_fit_per_object_ms"] = round(sum(spent.values()) / 2)
            rows.append(row)
            print("cold" if call == 0 else "warm", json.dumps(row), flush=True)


if __name__ == "__main__":
    run()
