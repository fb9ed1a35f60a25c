# ruff: noqa: E501
"""by_layout.py: post hoc, deciding nothing: part B's predicted rotate and zoom entries split by where 3D-SDN put the
edited car (the bench's per-entry `layout.mask_iou` of 3D-SDN: its drawn car against the target's), 3D-SDN - 2D PSNR
*all* by car in each part. Reads /tmp/s33/moves/out/<seed>_semantic/results.json. Run with PYTHONPATH=<main>/src."""
import json

from sdn3d.evaluation.paired import paired_difference

rows = []
for seed in ("2331", "2333", "2335"):
    (recs,) = json.load(open(f"/tmp/s33/moves/out/{seed}_semantic/results.json"))["entries"].values()
    for r in recs:
        m = (r.get("metrics") or {}).get("photo") or {}
        if r.get("edit_kind") not in ("rotate", "zoom") or "3d-sdn" not in m or "2d" not in m:
            continue
        rows.append((r["edit_kind"], m["3d-sdn"].get("layout", {}).get("mask_iou"), m["3d-sdn"]["all"]["psnr"],
                     m["2d"]["all"]["psnr"], f"{seed}:{r['cars']}"))
for kind in ("rotate", "zoom"):
    for name, test in (("layout IoU >= 0.5", lambda v: v is not None and v >= 0.5),
                       ("layout IoU < 0.5", lambda v: v is not None and v < 0.5)):
        sel = [x for x in rows if x[0] == kind and test(x[1])]
        if not sel:
            continue
        d = paired_difference([x[2] for x in sel], [x[3] for x in sel], True, groups=[x[4] for x in sel])
        print(f"predicted {kind}, {name}: {len(sel)} entries, {len(set(x[4] for x in sel))} cars: 3D-SDN - 2D PSNR all {d.mean:+.3f} [{d.low:+.3f}, {d.high:+.3f}] {d.wins}/{d.losses}")
