# ruff: noqa: E402, E501, E701, E702
"""fig_crops.py CAP.pt OUT.png KEY... : per car (KEY = world/frame/index-in-frame) the branch's lamp crops: clone, rain,
rain read through the air, and the red pixels (marked yellow) the cue finds in rain as main reads them and through the air."""
import math
import sys

import torch
from PIL import Image, ImageDraw

from sdn3d.geometric.lamps import LampCue, _red, through_the_air

rows = torch.load(sys.argv[1], weights_only=False)
S = 3


def find(world, var, frame, k):
    rr = [r for r in rows if r["key"] == (world, var, int(frame))]
    return rr[int(k)]


def img(t):
    return Image.fromarray((t.clamp(0, 1).permute(1, 2, 0).numpy() * 255).astype("uint8")).resize((t.shape[-1] * S, t.shape[-2] * S), Image.NEAREST)


def marked(seen, red):
    out = seen.clone(); out[:, red] = torch.tensor([1.0, 1.0, 0.0])[:, None]; return img(out)


tiles = []
for spec in sys.argv[3:]:
    w, f, k = spec.split("/")
    c, r = find(w, "clone", f, k), find(w, "rain", f, k)
    back = "back" if math.sin(r["true_ry"] - float(r["ray"])) < 0 else "front"
    cs, rs = c["seen"].float()[None], r["seen"].float()[None]; cm, rm = c["lamps"][None, 0], r["lamps"][None, 0]
    old = _red(rs, rm, LampCue(clear_dark=None))[0]; new = _red(rs, rm, LampCue())[0]
    thr = through_the_air(rs, rm, 0.10)[0] * rm[0]
    row = [(img(cs[0]), "clone"), (img(rs[0]), "rain"), (img(thr), "rain through the air"),
           (marked(rs[0], old), f"red as main reads: {int(old.sum())} px"), (marked(rs[0], new), f"red through the air: {int(new.sum())} px")]
    tiles.append((f"{w} frame {f}: a {back} view (truth)", row))
W = 5 * (64 * S + 6); H = len(tiles) * (64 * S + 34)
out = Image.new("RGB", (W, H), "white"); d = ImageDraw.Draw(out); y = 0
for title, row in tiles:
    d.text((2, y + 1), title, fill="black"); x = 0
    for t, name in row: out.paste(t, (x, y + 30)); d.text((x + 2, y + 16), name, fill="black"); x += t.width + 6
    y += 64 * S + 34
out.save(sys.argv[2], optimize=True)
