# ruff: noqa: E501
"""The demo's quality figures of two demo runs side by side (session 7's final run and this session's).

usage: python compare_quality.py RUN_A RUN_B [more runs...]  (each an sdn3d-demo output_dir)
Prints a markdown table and writes nothing.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

FIGURES = [
    ("semantic test mIoU", "semantic", "test/miou"),
    ("semantic test vehicle PQ", "semantic", "test/pq"),
    ("validation proposal recall", "semantic", "val/proposal_recall"),
    ("validation proposal precision", "semantic", "val/proposal_precision"),
    ("orientation similarity", "geometric", "test/orientation_similarity"),
    ("mesh accuracy", "geometric", "test/mesh_accuracy"),
    ("mesh majority floor", "geometric", "test/mesh_majority_floor"),
    ("reprojection error (image)", "geometric", "test/reprojection_error_image"),
    ("textural test PSNR dB", "textural", "test/psnr"),
]


def figures(run: Path) -> dict[str, str]:
    d = json.loads((run / "summary.json").read_text())
    row = {name: f"{d['training'][b]['metrics'][k]:.4g}" for name, b, k in FIGURES}
    r = d["proposal_recall"]
    row["test proposals found (recall / precision)"] = f"{r['recall'] * r['objects']:.0f} of {r['objects']} ({r['recall']:.3f} / {r['precision']:.3f})"
    comps = json.loads((run / "bench" / "results.json").read_text())["comparisons"]
    for source, label in (("semantic", "predicted"), ("gt", "oracle")):
        c = comps[source]["psnr/all"]
        row[f"Table 1 {label}: 3D-SDN - 2D, PSNR (all)"] = f"{c['mean']:+.2f} [{c['low']:+.2f}, {c['high']:+.2f}], {c['wins']}/{c['losses']}"
        c = comps[source]["l1/all"]
        row[f"Table 1 {label}: 3D-SDN - 2D, L1 (all)"] = f"{c['mean']:+.4f} [{c['low']:+.4f}, {c['high']:+.4f}], {c['wins']}/{c['losses']}"
    e = d["edits"]
    row["edits: frame, car"] = f"{e['frame']}, car {e['car']}"
    return row


def main(runs: list[str]) -> None:
    rows = [figures(Path(r)) for r in runs]
    print("| figure | " + " | ".join(runs) + " |")
    print("|---|" + "---|" * len(runs))
    for key in rows[0]:
        print(f"| {key} | " + " | ".join(r.get(key, "n/a") for r in rows) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
