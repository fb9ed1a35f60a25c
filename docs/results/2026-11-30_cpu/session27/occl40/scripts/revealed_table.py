"""revealed_table.py PRED.json ORACLE.json: revealed.py's per-entry rows of the predicted row and the ground-truth-mask
(oracle) row of the same Table 1 trees, grouped by what the predicted proposals made of the revealed car (unseen: it
shows no pixel in the source; own; merged into the removed proposal; missed), as a markdown table: entries, 3D-SDN -
2D paste (dB, per entry mean) on each row, the share of the rows' gap each group makes (summed over its entries,
divided by all entries), and the completion's part (its drawn pixels inside the revealed car's hidden pixels, and
outside them: 'stray'). Run with /work/main/.venv/bin/python (numpy only).
"""
import collections
import json
import re
import sys


def tree(run: str) -> int:
    """The tree's seed of a run name like main37_semantic or g037_semantic (the digits before the row)."""
    return int(re.search(r"(\d+)_(semantic|gt)$", run).group(1)[-2:])


def main(pred_path: str, oracle_path: str) -> None:
    pred = json.load(open(pred_path))
    oracle = {(tree(r["run"]), r["entry"]): r for r in json.load(open(oracle_path))}
    groups = collections.defaultdict(list)
    for r in pred:
        status = r["status"] if r.get("seen", 0) > 0 else "unseen"
        groups[status].append((r, oracle[(tree(r["run"]), r["entry"])]))
    n_all = len(pred)
    print("| revealed car (predicted proposals) | n | 3D - 2D predicted | 3D - 2D oracle | share of the gap "
          "| predicted: hidden px drawn, dB | predicted: stray px, dB | oracle: hidden px drawn, dB "
          "| oracle: stray px, dB |")
    print("|---|---|---|---|---|---|---|---|---|")
    for status in ("own", "merged", "missed", "unseen"):
        rows = groups.get(status, [])
        if not rows:
            continue
        n = len(rows)

        def mean(which: int, key: str, rows=rows, n=n) -> float:
            return sum(pair[which].get(key, 0) for pair in rows) / n

        gap = sum(o["d"] - p["d"] for p, o in rows) / n_all
        print(f"| {status} | {n} | {mean(0, 'd'):+.3f} | {mean(1, 'd'):+.3f} | {gap:+.3f} "
              f"| {mean(0, 'hid_drawn'):.0f}, {mean(0, 'db_hid_drawn'):+.3f} | {mean(0, 'stray'):.0f}, "
              f"{mean(0, 'db_stray'):+.3f} | {mean(1, 'hid_drawn'):.0f}, {mean(1, 'db_hid_drawn'):+.3f} "
              f"| {mean(1, 'stray'):.0f}, {mean(1, 'db_stray'):+.3f} |")
    p_all = sum(r["d"] for r in pred) / n_all
    o_all = sum(o["d"] for o in oracle.values()) / max(len(oracle), 1)
    print(f"| all | {n_all} | {p_all:+.3f} | {o_all:+.3f} | {o_all - p_all:+.3f} | | | | |")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
