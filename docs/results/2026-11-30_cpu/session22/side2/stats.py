"""Session 22 side2: per car of probe.py / realrec.py records (argv: the .pt files), where its body examples lie
against the lamps' heights (at the band, above it, below it; ``_lamp_band(..., corners=False)``) and their CIE Lab
medians, and the paint ``recolor.body_paint`` tells from each reference: main's (the examples off the band), the
whole body's, and the share of the examples off the band that are of the whole body's paint (session 21's rule).
With FILTER (a substring of the record's key) only those cars.

    PYTHONPATH=src /work/main/.venv/bin/python stats.py /tmp/s22data/side2/probe/*.pt
"""

from __future__ import annotations

import os
import sys

import torch

from sdn3d.editing.photo.recolor import body_paint
from sdn3d.meshes.templates import TEMPLATE_NAMES, TEMPLATE_SPECS
from sdn3d.meshes.vehicle_family import canonical_belt


def med(lab: torch.Tensor) -> str:
    if not len(lab):
        return "-"
    m = lab.median(0).values
    return f"({m[0]:.0f},{m[1]:.0f},{m[2]:.0f};c{float(lab[:, 1:].norm(dim=1).median()):.0f})"


def parts(rec: dict) -> dict[str, torch.Tensor]:
    """Boolean masks of the body examples: at the lamps' heights, above them, below them."""
    band = rec["band"]
    y = rec["feature"][:, 1]
    belt = canonical_belt(TEMPLATE_SPECS[TEMPLATE_NAMES[rec["template"]]])
    off = band < 0
    return {"at": ~off, "above": off & (y <= belt + 0.04), "below": off & (y >= belt + 0.20),
            "mid_off": off & (y > belt + 0.04) & (y < belt + 0.20)}


def share_of(paint: torch.Tensor, where: torch.Tensor) -> float:
    return float(paint[where].double().mean()) if bool(where.any()) else 0.0


def line(name: str, rec: dict) -> str:
    lab = rec["lab"]
    p = parts(rec)
    off = rec["band"] < 0
    _, main_col = body_paint(lab, reference=lab[off]) if int(off.sum()) >= 8 else body_paint(lab)
    whole_paint, whole_col = body_paint(lab)
    share = float(whole_paint[off].double().mean()) if whole_col and bool(off.any()) else 0.0
    return (f"{name} n{len(lab)} main_col {main_col} whole_col {whole_col} share_off {share:.2f} | "
            + " ".join(f"{k} {int(v.sum())} {med(lab[v])} wp{share_of(whole_paint, v):.2f}" for k, v in p.items()))


def main() -> int:
    flt = os.environ.get("FILTER", "")
    for path in sys.argv[1:]:
        recs = torch.load(path, weights_only=False)
        for name, rec in sorted(recs.items()):
            if flt in name and len(rec["lab"]) >= 8:
                print(path.rsplit("/", 1)[-1], line(name, rec))
    return 0


if __name__ == "__main__":
    sys.exit(main())
