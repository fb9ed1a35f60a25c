"""Whether two training runs' checkpoints hold the same weights: per tensor of the state_dict, bit-identical or the
largest absolute difference; and their summaries' test metrics side by side.
Usage: python same_weights.py RUN_A RUN_B"""
# ruff: noqa: T201
from __future__ import annotations

import json
import sys
from pathlib import Path

import torch


def main(a: str, b: str) -> None:
    ca = torch.load(Path(a) / "checkpoints" / "last.ckpt", map_location="cpu", weights_only=True)["state_dict"]
    cb = torch.load(Path(b) / "checkpoints" / "last.ckpt", map_location="cpu", weights_only=True)["state_dict"]
    same = [k for k in ca if torch.equal(ca[k], cb[k])]
    worst = max((float((ca[k].double() - cb[k].double()).abs().max()), k) for k in ca if k not in same and
                ca[k].is_floating_point()) if len(same) < len(ca) else (0.0, "")
    print(f"{a} vs {b}: {len(same)} of {len(ca)} tensors bit-identical; largest difference {worst[0]:.3g} ({worst[1]})")
    ma = json.loads((Path(a) / "summary.json").read_text())["metrics"]
    mb = json.loads((Path(b) / "summary.json").read_text())["metrics"]
    for key in ("test/miou", "test/pq", "test/proposal_recall", "test/proposal_precision", "test/loss"):
        print(f"  {key}: {ma.get(key)} vs {mb.get(key)}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
