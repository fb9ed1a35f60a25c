# ruff: noqa: E402, E501, E701, E702
"""lampvar.py TREE CAP.pt [VARIATION]: the lamp evidence at the true yaw (ground-truth geometry, oracle, for scoring)
of each captured proposal vehicle, read over different lamp regions built from its mask: as is, grown by k working
pixels (not into other proposals), filled between each row's ends. Counts: supports truth / opposes / no say."""
import sys

import torch
import torch.nn.functional as Fn

from sdn3d.data.scene_gt import frame_photo
from sdn3d.data.vkitti1 import read_frames
from sdn3d.derender import SURE_MASK
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.lamps import LampCue, evidence_of, red_lamps, white_lamps
from sdn3d.image_ops import crop_windows, mask_boxes, pixel_centre_boxes, square_crop_window

tree, cap = sys.argv[1:3]; var = sys.argv[3] if len(sys.argv) > 3 else None
rows = [r for r in torch.load(cap, weights_only=False) if var is None or r["var"] == var]
recs = index_records(read_frames(tree)); size = (312, 96); margin, S = 0.1, 64
cue = LampCue()
def grow(m, k): return Fn.max_pool2d(m[None, None].float(), 2 * k + 1, 1, k)[0, 0] > 0 if k else m
def rowfill(m):
    x = torch.arange(m.shape[1]); l = torch.where(m, x, 10**6).amin(1); r = torch.where(m, x, -1).amax(1)
    return (x[None] >= l[:, None]) & (x[None] <= r[:, None])
def colfill(m): return rowfill(m.T).T
from sdn3d.proposal_fit import unsure_below


def band(m, o, f=0.3): return (m | (unsure_below(m[None], f)[0])) & ~o
def notop(reg, m, q=1/3):
    rows = m.any(1).nonzero().flatten(); t, b = int(rows.min()), int(rows.max())
    keep = torch.arange(m.shape[0]) >= t + q * (b - t + 1)
    return reg & keep[:, None]
V = {"FGband": band, "Fband": band, "Fband15": lambda m, o: band(m, o, 0.15), "band": band, "Rband": band, "Rband15": lambda m, o: band(m, o, 0.15), "Rband_notop": lambda m, o: notop(band(m, o), m), "band15": lambda m, o: band(m, o, 0.15), "band_notop": lambda m, o: notop(band(m, o), m), "notop": lambda m, o: notop(m, m), "notop4": lambda m, o: notop(m, m, 0.25),
     "band_g1": lambda m, o: grow(band(m, o), 1) & ~o, "asis": lambda m, o: m, "g1": lambda m, o: grow(m, 1) & ~o, "g2": lambda m, o: grow(m, 2) & ~o, "g3": lambda m, o: grow(m, 3) & ~o,
     "rowfill": lambda m, o: rowfill(m) & ~o, "fill": lambda m, o: (rowfill(m) | colfill(m)) & ~o, "fill_g1": lambda m, o: grow(rowfill(m) | colfill(m), 1) & ~o}
import sys as _s

MARGIN = float(_s.argv[4]) if len(_s.argv) > 4 else None
count = {k: [0, 0, 0] for k in V}
photos = {}
EV = {}
for r in rows:
    if "net_ry" not in r: continue
    m = r["mask"]; others = r["all_masks"].any(0) & ~m if r["all_masks"].shape[0] > 1 else torch.zeros_like(m)
    others = (r["all_masks"].sum(0) - m.long()) > 0
    box = pixel_centre_boxes(mask_boxes(m[None]))[0]
    win = torch.tensor([square_crop_window(box, MARGIN or 0.1)], dtype=torch.float32)
    if r["key"] not in photos: photos = {r["key"]: frame_photo(recs[r["key"]], size)}
    crop = photos[r["key"]].crops(win, S)
    alpha = torch.tensor([[r["true_ry"] - float(r["ray"])]])
    for k, f in V.items():
        reg = f(m, others)
        lm = (crop_windows(reg[None, None].float(), win, S, "bilinear") >= SURE_MASK).float()
        seen = crop * lm
        if k.startswith("F"):
            lm0 = (crop_windows(m[None, None].float(), win, S, "bilinear") >= SURE_MASK).float()
            r0 = red_lamps(crop * lm0, lm0, cue); r1 = red_lamps(seen, lm, cue)
            keep = r0[0] & r0[1] if k.startswith("FG") else r0[0]
            red = tuple(torch.where(keep, a, b) for a, b in zip(r0, r1, strict=True))
            e = float(evidence_of(*red, alpha, cue, front=white_lamps(crop * lm0, lm0, cue))[0, 0])
        elif k.startswith("R"):
            lm0 = (crop_windows(m[None, None].float(), win, S, "bilinear") >= SURE_MASK).float()
            e = float(evidence_of(*red_lamps(seen, lm, cue), alpha, cue, front=white_lamps(crop * lm0, lm0, cue))[0, 0])
        else:
            e = float(evidence_of(*red_lamps(seen, lm, cue), alpha, cue, front=white_lamps(seen, lm, cue))[0, 0])
        count[k][0 if e > 1e-6 else 1 if e < -1e-6 else 2] += 1
        EV.setdefault((r['key'], r['gt_id']), {})[k] = (round(e, 2), int(lm.sum()))
print(cap.split("/")[-1], var, "n", sum(count["asis"]), {k: f"{v[0]}+/{v[1]}-/{v[2]}0" for k, v in count.items()})
if len(sys.argv) > 5:
    for key, d in EV.items():
        if len({v[0] > 0 for v in d.values()}) > 1 or d['asis'][0] <= 0: print(key, d)
