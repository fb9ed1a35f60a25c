# ruff: noqa: E501, E701, E702
"""entries.py POSES.json: every entry of one run (poses.py's json), ranked by 3D-SDN minus 2D paste PSNR all (dB),
one line each: index, key, kind, the difference (all, objects), the cause class (causes.py's rule, losers only),
ana.py's linearised per-pixel shares, and per operation the turn, zoom and the fitted pose against the truth
(oracle, scoring only)."""
import importlib.util
import json
import os
import sys

spec = importlib.util.spec_from_file_location("causes_rules", os.path.join(os.path.dirname(__file__), "causes.py"))
causes = importlib.util.module_from_spec(spec); spec.loader.exec_module(causes)
rows = sorted(json.load(open(sys.argv[1])), key=lambda r: r["d_all"])
print(f"# {sys.argv[1]}: {len(rows)} entries, ranked by 3D-2D PSNR all")
print("# idx key kind d_all d_obj | cause | T&drawn ~T&drawn T&fill ~T&fill T&input | ops (turn deg, zoom, fit yaw err deg, template fit/true, distance ratio, length ratio, proposal IoU)")
for r in rows:
    ops = "; ".join(o["type"][:3] + (f" {o['turn_deg']:+.0f} x{o['zoom']:.2f}" if o["type"] == "modify" else "")
                    + (f" yaw{o['yaw_err']:+.0f} t{o['tpl'][0]}/{o['tpl'][1]} d{o['dist_ratio']:.2f} l{o['len_ratio']:.2f}" if "yaw_err" in o else "")
                    + (f" iou{o['mask_iou']:.2f}" if "mask_iou" in o else "") for o in r["ops"])
    cls = " ".join(f"{r.get(n, 0):+.2f}" for n in ("T&drawn", "~T&drawn", "T&fill", "~T&fill", "T&input"))
    c = causes.cause(r) if r["d_all"] < 0 else "-"
    print(f"{r['index']:3d} {r['key']:24s} {r['kind']:16s} {r['d_all']:+6.2f} {r['d_obj']:+6.2f} | {c} | {cls} | {ops}")
