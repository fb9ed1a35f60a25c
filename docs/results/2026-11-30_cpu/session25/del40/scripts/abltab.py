"""abltab.py T1_DIR BASE VARIANT[,VARIANT...] SEED[,SEED...]: a markdown table of Table 1 photo runs
(T1_DIR/<name><SEED>_<row>/results.json, t1.sh's layout) per row (predicted, oracle), kind (delete, occluder
removed, both) and variant: 3D-SDN variant minus BASE (paired per entry) and 3D-SDN variant minus the 2D paste, on
PSNR 'all' (dB) and L1 'all' (signed: positive = better), mean [10k paired bootstrap 95 % interval, seed 0] wins/losses.
Entries missing from either run of a pair (or runs
not made yet) are left out."""
import json
import os
import sys

from perentry import ci


def load(run: str) -> dict[int, tuple[str, dict, dict]]:
    out = {}
    for e in list(json.load(open(f"{run}/results.json"))["entries"].values())[0]:
        m = (e.get("metrics") or {}).get("photo") or {}
        if "3d-sdn" in m and "2d" in m:
            out[e["index"]] = (e["edit_kind"], m["3d-sdn"]["all"], m["2d"]["all"])
    return out


def main(t1: str, base: str, variants: list[str], seeds: list[str]) -> None:
    print("| row | kind | code | n | 3D-SDN code - base, PSNR all | L1 all | 3D-SDN - 2D (code), PSNR all | L1 all |")
    print("|---|---|---|---|---|---|---|---|")
    for row, label in (("semantic", "predicted"), ("gt", "ground-truth masks (oracle)")):
        for kinds in (("delete",), ("occluder_removed",), ("delete", "occluder_removed")):
            for v in [base] + variants:
                pairs = []
                for s in seeds:
                    if not os.path.exists(f"{t1}/{v}{s}_{row}/results.json"):
                        continue
                    a, b = load(f"{t1}/{base}{s}_{row}"), load(f"{t1}/{v}{s}_{row}")
                    pairs += [(a[i], b[i]) for i in sorted(set(a) & set(b)) if a[i][0] in kinds]
                if not pairs:
                    continue
                dp = [n[1]["psnr"] - o[1]["psnr"] for o, n in pairs]
                dl = [o[1]["l1"] - n[1]["l1"] for o, n in pairs]
                gp = [n[1]["psnr"] - n[2]["psnr"] for _, n in pairs]
                gl = [n[2]["l1"] - n[1]["l1"] for _, n in pairs]
                kind = " + ".join(kinds).replace("occluder_removed", "occluder removed")
                print(f"| {label} | {kind} | {v} | {len(pairs)} | {ci(dp)} | {ci(dl)} | {ci(gp)} | {ci(gl)} |")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3].split(","), sys.argv[4].split(","))
