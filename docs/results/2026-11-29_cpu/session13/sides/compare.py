# ruff: noqa: E501
"""compare.py BASE_VARIANT FILE.json [FILE.json ...] [--only V1,V2]: each variant of variants.py's outputs (or, with
two bench outputs, ``--bench OURS.json BASE.json``: sdn3d-bench counterfactual=true's photo:rays) against
BASE_VARIANT, per source scene and turn bin, pooled over the files given (pairs keyed by file and pair): mean PSNR /
L1 / flat-colour share on the car's target pixels, the paired difference (10k bootstrap resamples, 95 %) and
wins/losses/ties."""

from __future__ import annotations

import json
import sys
from collections import defaultdict

from sdn3d.evaluation.paired import paired_difference

LABELS = {"oracle": "ground-truth geometry (oracle)", "gt": "ground-truth masks (oracle)", "semantic": "predicted"}
BINS = ("turn 15", "turn 45", "turn 90", "turn 180")


def load_variants(paths: list[str]) -> dict:
    """{(source, bin): {variant: {pair id: (psnr, l1, flat)}}}"""
    out: dict = defaultdict(lambda: defaultdict(dict))
    for path in paths:
        for p in json.load(open(path))["pairs"]:
            for method, m in p["metrics"].items():
                variant = method.split("|", 1)[1] if "|" in method else method
                car = m.get("car", {})
                out[(p["source"], p["bin"])][variant][(path, p["key"])] = (car.get("psnr"), car.get("l1"), car.get("flat"))
    return out


def load_bench(ours: str, base: str) -> dict:
    out: dict = defaultdict(lambda: defaultdict(dict))
    for name, path in (("branch", ours), ("main", base)):
        for p in json.load(open(path))["pairs"]:
            car = p["metrics"].get("photo:rays", {}).get("car")
            if car:
                out[(p["source"], p["bin"])][name][p["key"]] = (car.get("psnr"), car.get("l1"), car.get("flat"))
    return out


def main() -> None:
    args = sys.argv[1:]
    only = None
    if "--only" in args:
        i = args.index("--only")
        only = args[i + 1].split(",")
        del args[i:i + 2]
    if args[0] == "--bench":
        data, base = load_bench(args[1], args[2]), "main"
        print(f"ours (branch): {args[1]}\nbase (main): {args[2]}\nmethod: photo:rays\n")
    else:
        base, data = args[0], load_variants(args[1:])
        print(f"files: {', '.join(args[1:])}\nbase variant: {base}\n")
    print("| source scene | bin | variant | n | PSNR base | PSNR variant | difference [95 % CI] | wins/losses/ties | L1 difference [95 % CI] | flat share base / variant |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for (source, bin_) in sorted(data, key=lambda k: (k[0] != "oracle", BINS.index(k[1]) if k[1] in BINS else 9)):
        by = data[(source, bin_)]
        for variant in sorted(by, key=lambda v: (v != base, v)):
            if variant == base or (only and variant not in only):
                continue
            keys = [k for k in by[variant] if k in by[base] and by[variant][k][0] is not None and by[base][k][0] is not None]
            if not keys:
                continue
            a = [by[variant][k] for k in keys]
            b = [by[base][k] for k in keys]
            d = paired_difference([x[0] for x in a], [x[0] for x in b], True, samples=10000)
            l1 = paired_difference([x[1] for x in a], [x[1] for x in b], False, samples=10000)
            flat_a = sum(x[2] for x in a) / len(a)
            flat_b = sum(x[2] for x in b) / len(b)
            print(f"| {LABELS.get(source, source)} | {bin_} | {variant} | {d.n} | {sum(x[0] for x in b) / len(b):.2f} | "
                  f"{sum(x[0] for x in a) / len(a):.2f} | {d.mean:+.3f} [{d.low:+.3f}, {d.high:+.3f}] | {d.wins}/{d.losses}/{d.ties} | "
                  f"{l1.mean:+.4f} [{l1.low:+.4f}, {l1.high:+.4f}] | {100 * flat_b:.1f} % / {100 * flat_a:.1f} % |")


if __name__ == "__main__":
    main()
