# ruff: noqa: E501
"""variants.py VARIANT_DIR MAIN_DIR: probe.py (session 14) outputs of census.sh for a variant and for main, per tree and
bin (cf31/cf33, turns 45/90, ground-truth geometry (oracle)): the mean per-pair PSNR difference and every changed pair."""

import json
import sys


def load(path: str) -> dict:
    return {json.loads(line)["key"]: json.loads(line) for line in open(path) if line.startswith("{")}


def main() -> None:
    new_dir, main_dir = sys.argv[1], sys.argv[2]
    for t in ("cf31_45", "cf31_90", "cf33_45", "cf33_90"):
        new, base = load(f"{new_dir}/{t}.log"), load(f"{main_dir}/{t}.log")
        d = {k: new[k]["psnr"] - base[k]["psnr"] for k in new if k in base}
        changed = {k: v for k, v in d.items() if abs(v) > 1e-6}
        print(t, "n", len(d), f"mean diff {sum(d.values()) / len(d):.4f}", "changed", len(changed))
        for k, v in sorted(changed.items(), key=lambda kv: kv[1]):
            print(f"   {k:40s} {v:+.3f}  (main {base[k]['psnr']:.2f})")


if __name__ == "__main__":
    main()
