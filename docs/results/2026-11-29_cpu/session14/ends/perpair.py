# ruff: noqa: E501
"""perpair.py NEW.json BASE.json [BIN]: per turn pair of two sdn3d-bench counterfactual=true outputs (photo:rays), the
car-pixel PSNR of base and new and their difference, sorted by the difference (BIN: only that bin, e.g. "turn 45")."""

from __future__ import annotations

import json
import sys


def load(path: str) -> dict:
    out = {}
    for p in json.load(open(path))["pairs"]:
        car = p["metrics"].get("photo:rays", {}).get("car")
        if car:
            out[(p["source"], p["bin"], p["key"])] = car["psnr"]
    return out


def main() -> None:
    new, base = load(sys.argv[1]), load(sys.argv[2])
    want = sys.argv[3] if len(sys.argv) > 3 else None
    rows = [(new[k] - base[k], k, base[k], new[k]) for k in new if k in base and (want is None or k[1] == want)]
    for d, k, b, n in sorted(rows):
        if abs(d) > 1e-6:
            print(f"{d:+.3f}  {b:.2f} -> {n:.2f}  {k[0]} {k[1]} {k[2]}")


if __name__ == "__main__":
    main()
