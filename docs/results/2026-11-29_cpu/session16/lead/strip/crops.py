# ruff: noqa: E402, E501, E702, I001, B905
import sys
from PIL import Image, ImageDraw
root = sys.argv[1]; out = sys.argv[2]
src = Image.open('/work/main/tests/data/0006_30-deg-right_00043.png').convert('RGB')
boxes = {'12001': (466, 203, 666, 333), '12002': (704, 194, 917, 305)}
rows = []
for iid, (l, t, r, b) in boxes.items():
    box = (l - 60, t - 40, r + 60, b + 30)
    tiles = [('input', src.crop(box))]
    for fill in ('rays', 'learnt'):
        tiles.append((f'{iid} deleted, fill={fill}', Image.open(f'{root}/{iid}_{fill}/out/edited.png').convert('RGB').crop(box)))
    w, h = tiles[0][1].size
    s = 2
    row = Image.new('RGB', (len(tiles) * w * s, h * s + 18), 'white')
    d = ImageDraw.Draw(row)
    for k, (name, im) in enumerate(tiles):
        row.paste(im.resize((w * s, h * s), Image.NEAREST), (k * w * s, 18))
        d.text((k * w * s + 4, 3), name, fill='black')
    rows.append(row)
W = max(r.size[0] for r in rows); H = sum(r.size[1] for r in rows)
img = Image.new('RGB', (W, H), 'white'); y = 0
for r in rows:
    img.paste(r, (0, y)); y += r.size[1]
img.save(out)
