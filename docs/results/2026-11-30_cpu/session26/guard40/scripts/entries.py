"""entries.py MAIN_RUN BRANCH_RUN: the Table 1 entries (dbench.py runs' results.json, loaded by session 13 rotloss's
paired.py's load(), as compare.py does) whose 3D-SDN PSNR *all* differs between two codes, largest change first:
entry, kind, main, branch, branch - main (dB)."""
import sys

PAIRED = "/work/main/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py"
ns: dict = {}
exec(compile(open(PAIRED).read().split("\nlabel, pairs")[0], PAIRED, "exec"), ns)  # its load() and ci() only


def main(base: str, new: str) -> None:
    a, b = ns["load"](base), ns["load"](new)
    rows = []
    for i in sorted(set(a) & set(b)):
        m, r = a[i][2]["all"]["psnr"], b[i][2]["all"]["psnr"]
        if abs(r - m) > 1e-6:
            rows.append((abs(r - m), f"entry {i} {a[i][0]}: main {m:.3f} branch {r:.3f} br-main {r - m:+.3f} dB"))
    for _, line in sorted(rows, reverse=True):
        print(line)


if __name__ == "__main__":
    main(*sys.argv[1:3])
