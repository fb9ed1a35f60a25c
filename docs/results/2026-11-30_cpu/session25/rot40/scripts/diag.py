"""Per-entry diagnosis of the predicted rotates / zooms of one Table 1 run pair (dbench.py dumps).

python diag.py PRED_RUN GT_RUN [OUT.json]   (PRED_RUN: <name><seed>_semantic, GT_RUN: <name><seed>_gt; each with its
results.json and its .dump folder). For every rotate / zoom entry: 3D-SDN - 2D PSNR (all) with the semantic branch's
proposals (predicted) and with ground-truth masks (oracle); the picked proposal's mask against the edited car's
ground-truth mask in the source (IoU, share of the proposal on other cars, share of the car it covers); the drawn
car (pixels not left as input or fill) against the car's ground-truth mask in the target (IoU, pixels drawn past it,
share of it left undrawn); the same for the oracle run."""
import json
import sys

import numpy as np

DRAWN = (1, 2, 3, 5, 7, 8, 9, 11)  # photo, mirror, fallback, recolored, part, default, relit, another car


def psnr_all(entry, method):
    return entry["metrics"]["photo"][method]["all"]["psnr"]


def load(run):
    res = json.load(open(f"{run}/results.json"))
    entries = next(iter(res["entries"].values())) if isinstance(res["entries"], dict) else res["entries"]
    return {e["index"]: e for e in entries}


def masks(z):
    gid = int(z["gt_ids"][0]) if len(z["gt_ids"]) else -1
    pick = int(z["picks"][0]) if len(z["picks"]) else -1
    car_s, car_t = z["src_inst"] == gid, z["tgt_inst"] == gid
    prop = z["proposals"] == pick
    drawn = np.isin(z["code"], DRAWN)
    return gid, car_s, car_t, prop, drawn


def iou(a, b):
    u = (a | b).sum()
    return float((a & b).sum() / u) if u else 0.0


def row(z):
    gid, car_s, car_t, prop, drawn = masks(z)
    other = (z["src_inst"] > 0) & ~car_s & (z["src_inst"] // 1000 == gid // 1000) if gid > 0 else np.zeros_like(prop)
    pick = int(z["picks"][0]) if len(z["picks"]) else -1
    return {"gt_id": gid, "pick": pick, "prop_iou": iou(prop, car_s),
            "prop_on_other_car": float((prop & other).sum() / max(prop.sum(), 1)),
            "prop_recall": float((prop & car_s).sum() / max(car_s.sum(), 1)), "prop_px": int(prop.sum()),
            "car_px": int(car_s.sum()), "car_t_px": int(car_t.sum()),
            "draw_iou": iou(drawn, car_t), "draw_past": float((drawn & ~car_t).sum() / max(car_t.sum(), 1)),
            "draw_miss": float((car_t & ~drawn).sum() / max(car_t.sum(), 1)), "draw_px": int(drawn.sum()),
            "objects": str(z["objects"])}


def main():
    pred, gt = sys.argv[1], sys.argv[2]
    ep, eg = load(pred), load(gt)
    rows = []
    for i, e in sorted(ep.items()):
        if e.get("edit_kind") not in ("rotate", "zoom") or e["kind"] != "edit" or e["errors"]:
            continue
        r = {"index": i, "key": e["key"], "kind": e["edit_kind"],
             "pred": psnr_all(e, "3d-sdn") - psnr_all(e, "2d")}
        if i in eg and not eg[i]["errors"]:
            r["oracle"] = psnr_all(eg[i], "3d-sdn") - psnr_all(eg[i], "2d")
        try:
            zp = np.load(f"{pred}.dump/{i:04d}.npz", allow_pickle=True)
            r.update(row(zp))
            zg = np.load(f"{gt}.dump/{i:04d}.npz", allow_pickle=True)
            rg = row(zg)
            r.update({"o_draw_iou": rg["draw_iou"], "o_draw_past": rg["draw_past"], "o_draw_miss": rg["draw_miss"]})
        except FileNotFoundError:
            pass
        rows.append(r)
    if len(sys.argv) > 3:
        json.dump(rows, open(sys.argv[3], "w"), indent=1)
    cols = ["prop_iou", "prop_on_other_car", "prop_recall", "draw_iou", "draw_past", "draw_miss", "o_draw_iou",
            "o_draw_past", "o_draw_miss"]
    print("idx kind   pred   orac " + " ".join(c[:9] for c in cols) + " key")
    for r in sorted(rows, key=lambda r: r["pred"]):
        print(f"{r['index']:3d} {r['kind'][:4]} {r['pred']:+6.2f} {r.get('oracle', float('nan')):+6.2f} "
              + " ".join(f"{r.get(c, float('nan')):9.2f}" for c in cols) + f" {r['key']} {r.get('objects', '')}")
    lose = [r for r in rows if r["pred"] < 0 and r.get("oracle", -1) > 0]
    print(f"{len(rows)} entries, {sum(r['pred'] < 0 for r in rows)} lose predicted, {len(lose)} of them win oracle")


if __name__ == "__main__":
    main()
