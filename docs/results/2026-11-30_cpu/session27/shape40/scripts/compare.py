# ruff: noqa: E501
"""compare.py LABEL MAIN_RUN:BRANCH_RUN [...]: Table 1 photo rows (results.json of session 11's dbench.py runs) pooled
over pairs of runs (one pair per tree), per kind of edit: 3D-SDN branch minus main, the 2D paste branch minus main (it
uses the same pick), and the gap 3D-SDN minus 2D of main and of the branch with its change (paired per entry), on PSNR
and L1 of 'all' and 'objects' (L1 signed so that positive = branch / 3D-SDN better). Mean, 10k-draw paired bootstrap
95 % interval (seed 0), wins/losses (n): session 13 rotloss's paired.py's load() and ci(). Entries a method failed on
are counted per run and left out of the pairs."""
import json
import os
import sys

PAIRED = "/work/main/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py"
ns: dict = {}
exec(compile(open(PAIRED).read().split("\nlabel, pairs")[0], PAIRED, "exec"), ns)  # its load() and ci() only
load, ci = ns["load"], ns["ci"]


def failures(run: str) -> str:
    entries = list(json.load(open(f"{run}/results.json"))["entries"].values())[0]
    bad = {}
    for e in entries:
        for method in e.get("errors") or {}:
            bad[method] = bad.get(method, 0) + 1
    return f"{os.path.basename(run)}: {len(entries)} entries, failed {bad or 'none'}"


def main(label: str, pairs: list[list[str]]) -> None:
    rows = []
    for base, new in pairs:
        a, b = load(base), load(new)
        rows += [(a[i], b[i]) for i in sorted(set(a) & set(b))]
        print(f"   {failures(base)}; {failures(new)}")
    print(f"== {label}: {len(rows)} paired entries from {len(pairs)} tree(s)")
    for metric, region, sign in (("psnr", "all", 1), ("l1", "all", -1), ("psnr", "objects", 1), ("l1", "objects", -1)):
        print(f"-- {metric} {region}" + (" (signed: positive = branch / 3D-SDN better)" if sign < 0 else ""))
        for kind in ["ALL"] + sorted({r[0][0] for r in rows}):
            sel = [r for r in rows if (kind == "ALL" or r[0][0] == kind) and region in r[0][2] and region in r[1][2]
                   and region in r[0][3] and region in r[1][3]]
            if not sel:
                continue
            sdn = [sign * (n[2][region][metric] - b[2][region][metric]) for b, n in sel]
            d2 = [sign * (n[3][region][metric] - b[3][region][metric]) for b, n in sel]
            gap_main = [sign * (b[2][region][metric] - b[3][region][metric]) for b, _ in sel]
            gap_new = [sign * (n[2][region][metric] - n[3][region][metric]) for _, n in sel]
            change = [y - x for x, y in zip(gap_main, gap_new, strict=True)]
            print(f"{kind:16s} 3D br-main {ci(sdn)} | 2D br-main {ci(d2)} | 3D-2D main {ci(gap_main)} | "
                  f"3D-2D branch {ci(gap_new)} | gap change {ci(change)}")


if __name__ == "__main__":
    main(sys.argv[1], [p.split(":") for p in sys.argv[2:]])
