# ruff: noqa: E501
"""worst.py BASE_RUN NEW_RUN WEATHER N: the N entries of one weather whose 3D-SDN PSNR (all, photo) fell most from the
base run to the new (runs: /tmp/s12data/cutmask/runs/<NAME>/results.json); prints index, key, kind, base, new."""
import json
import sys

D = "/tmp/s12data/cutmask/runs/"
base, new, weather, n = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])


def load(name):
    r = json.load(open(f"{D}{name}/results.json"))
    return {e["index"]: e for e in list(r["entries"].values())[0] if (e.get("metrics") or {}).get("photo")}


b, a = load(base), load(new)
rows = []
for i, e in b.items():
    if i in a and f"/{weather} " in e["key"] and "3d-sdn" in e["metrics"]["photo"] and "3d-sdn" in a[i]["metrics"]["photo"]:
        pb, pa = e["metrics"]["photo"]["3d-sdn"]["all"]["psnr"], a[i]["metrics"]["photo"]["3d-sdn"]["all"]["psnr"]
        rows.append((pa - pb, i, e["key"], e["edit_kind"], pb, pa))
for d, i, key, kind, pb, pa in sorted(rows)[:n]:
    print(f"{i:04d} {key} {kind} base {pb:.2f} new {pa:.2f} ({d:+.2f})")
