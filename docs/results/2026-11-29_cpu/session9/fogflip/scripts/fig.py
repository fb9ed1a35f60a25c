# ruff: noqa: E402, E501, E701, E702
"""fig.py OUT.png ROW...: ROW = 'TITLE|BASE_EXAMPLE.png|NEW_EXAMPLE.png|X0,Y0,X1,Y1': per row the crop (working
pixels, enlarged 4x) of source | target | 3D-SDN before | 3D-SDN after | 2D paste, every panel titled."""
import sys

from PIL import Image, ImageDraw

S = 4; PW = 312


def panel(path, k, box):
    im = Image.open(path).convert("RGB"); W, H = im.size; gap = (W - 5 * PW) // 4; top = H - 96
    x0, y0, x1, y1 = box
    return im.crop((k * (PW + gap) + x0, top + y0, k * (PW + gap) + x1, top + y1)).resize(((x1 - x0) * S, (y1 - y0) * S), Image.NEAREST)


rows = []
for spec in sys.argv[2:]:
    title, base, new, box = spec.split("|"); box = tuple(int(v) for v in box.split(","))
    tiles = [(panel(base, 0, box), "source"), (panel(base, 1, box), "target (truth)"), (panel(base, 2, box), "3D-SDN before"),
             (panel(new, 2, box), "3D-SDN after"), (panel(base, 3, box), "2D paste")]
    w = sum(t.width for t, _ in tiles) + 4 * 4; h = tiles[0][0].height + 30
    row = Image.new("RGB", (w, h), "white"); d = ImageDraw.Draw(row); d.text((2, 1), title, fill="black"); x = 0
    for t, name in tiles: row.paste(t, (x, 30)); d.text((x + 2, 16), name, fill="black"); x += t.width + 4
    rows.append(row)
out = Image.new("RGB", (max(r.width for r in rows), sum(r.height + 6 for r in rows)), "white"); y = 0
for r in rows: out.paste(r, (0, y)); y += r.height + 6
out.save(sys.argv[1], optimize=True)
