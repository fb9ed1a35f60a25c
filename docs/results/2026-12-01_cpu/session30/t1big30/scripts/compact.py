# ruff: noqa: E501
"""compact.py TABLES_DIR: the README's compact pooled table from tables.py's t1.json: per row and kind, n (groups),
each column's 3D-SDN - 2D [95 %] wins/losses, 3D-SDN / 2D / floor PSNR all means, and the goal. Session 30 t1big30."""
import json
import sys

t = json.load(open(f"{sys.argv[1]}/t1.json"))["pooled"]
print("| row | kind | n (groups) | PSNR all: 3D-SDN / 2D / source | 3D-2D PSNR all | 3D-2D L1 all | 3D-2D PSNR objects | "
      "3D-2D L1 objects | goal |")
print("|---|---|---|---|---|---|---|---|---|")
for row, name in (("semantic", "predicted"), ("gt", "GT masks (oracle)")):
    for kind in ("rotate", "zoom", "delete", "occluder_removed", "all kinds"):
        c = t[f"{row}|pooled|{kind}"]
        cells = []
        for col in ("psnr/all", "l1/all", "psnr/objects", "l1/objects"):
            if col not in c:
                cells.append("(no region)")
                continue
            d = c[col]["diff"]
            f = "{:+.3f}" if col.startswith("psnr") else "{:+.4f}"
            mark = "**" if d["verdict"] == "better" else ""
            cells.append(f"{mark}{f.format(d['mean'])} [{f.format(d['low'])}, {f.format(d['high'])}]{mark} "
                         f"{d['wins']}/{d['losses']}")
        vs = [c[col]["diff"]["verdict"] for col in c]
        goal = "yes" if all(v == "better" for v in vs) else f"no ({sum(v != 'better' for v in vs)} unclear)"
        a = c["psnr/all"]
        print(f"| {name} | {kind} | {a['n']} ({a['diff']['groups']}) | {a['3d-sdn']:.2f} / {a['2d']:.2f} / "
              f"{a['source']:.2f} | " + " | ".join(cells) + f" | {goal} |")
