"""brmain.py DIR MAIN BRANCH SEED...: Table 1 photo runs DIR/<MAIN><SEED>_<row> against DIR/<BRANCH><SEED>_<row>
(dbench.py's results.json; rows semantic = predicted, gt = ground-truth masks (oracle)), paired per entry: per row
and kind, 3D-SDN PSNR 'all' branch - main, 3D-SDN - 2D on main and on the branch, the 2D paste's branch - main (mean,
10k paired bootstrap 95 % interval, seed 0, wins/losses, n: perentry.ci); then per tree, the predicted and oracle
deletes' branch - main. Prints markdown. Run from this folder (imports perentry).
Session 26 del41's script; here a row whose runs are missing is left out
(frag40 runs the predicted row alone: the change is in the proposals, which the oracle row does not use)."""
import json
import os
import sys

from perentry import ci

ROWS = {"semantic": "predicted", "gt": "ground-truth masks (oracle)"}


def load(run: str) -> dict[int, tuple[str, float, float]]:
    out = {}
    for e in list(json.load(open(f"{run}/results.json"))["entries"].values())[0]:
        m = (e.get("metrics") or {}).get("photo") or {}
        if "3d-sdn" in m and "2d" in m:
            out[e["index"]] = (e["edit_kind"], m["3d-sdn"]["all"]["psnr"], m["2d"]["all"]["psnr"])
    return out


def main(root: str, base: str, new: str, seeds: list[str]) -> None:
    print(f"| row | kind | n | 3D-SDN {new} - {base} | 3D-SDN - 2D, {base} | 3D-SDN - 2D, {new} | 2D {new} - {base} |")
    print("|---|---|---|---|---|---|---|")
    per_tree = []
    for row, label in ROWS.items():
        pairs: dict[str, list] = {}
        if not all(os.path.exists(f"{root}/{code}{seed}_{row}") for code in (base, new) for seed in seeds):
            continue
        for seed in seeds:
            a, b = load(f"{root}/{base}{seed}_{row}"), load(f"{root}/{new}{seed}_{row}")
            for i in sorted(set(a) & set(b)):
                pairs.setdefault(a[i][0], []).append((seed, a[i], b[i]))
        for kind in ["all kinds"] + sorted(pairs):
            sel = [p for k, v in pairs.items() for p in v] if kind == "all kinds" else pairs[kind]
            cells = [ci([n[1] - m[1] for _, m, n in sel]), ci([m[1] - m[2] for _, m, _ in sel]),
                     ci([n[1] - n[2] for _, _, n in sel]), ci([n[2] - m[2] for _, m, n in sel])]
            print(f"| {label} | {kind} | {len(sel)} | " + " | ".join(cells) + " |")
        for seed in seeds:
            sel = [(m, n) for s, m, n in pairs.get("delete", []) if s == seed]
            per_tree.append(f"{label} deletes, tree {seed}: {ci([n[1] - m[1] for m, n in sel])}")
    print()
    for line in per_tree:
        print(f"- {line}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:])
