# ruff: noqa: E402, E501, E701, E702
"""pics.py REAL OUT.png: the real frame's deletes (real.sh's outputs), input | rays | learnt per car, cropped, labelled."""
import sys
from pathlib import Path

from PIL import Image, ImageDraw, ImageFont

real, out = Path(sys.argv[1]), sys.argv[2]
src = Image.open('/work/main/tests/data/0006_30-deg-right_00043.png').convert('RGB')
crops = {'12001': ('red car 12001', (400, 150, 740, 370)), '12002': ('black car 12002', (650, 150, 990, 370))}
scale, pad, title = 1.25, 8, 26
try:
    font = ImageFont.truetype('DejaVuSans.ttf', 18)
except OSError:
    font = ImageFont.load_default()
rows = []
for iid, (name, box) in crops.items():
    panels = [(f'input ({name})', src)]
    for fill in ('rays', 'learnt'):
        panels.append((f'deleted, photo.fill={fill}' + (' (default)' if fill == 'rays' else ''),
                       Image.open(real / f'{iid}_{fill}' / 'out' / 'edited.png').convert('RGB')))
    rows.append([(t, im.crop(box).resize((int((box[2] - box[0]) * scale), int((box[3] - box[1]) * scale)))) for t, im in panels])
w = sum(p.width for _, p in rows[0]) + pad * (len(rows[0]) + 1)
h = sum(r[0][1].height + title for r in rows) + pad * (len(rows) + 1)
canvas = Image.new('RGB', (w, h), 'white'); d = ImageDraw.Draw(canvas)
y = pad
for r in rows:
    x = pad
    for t, p in r:
        d.text((x, y), t, fill='black', font=font); canvas.paste(p, (x, y + title)); x += p.width + pad
    y += r[0][1].height + title + pad
canvas.save(out)

# The holes' far edge at 2x: rays | learnt, per car (where the learnt fill's dark smudges are).
zoom = [(f'{name} deleted, fill={fill}, far edge x2', Image.open(real / f'{iid}_{fill}' / 'out' / 'edited.png').convert('RGB').crop(box).resize((520, 280)))
        for iid, name, box in (('12002', 'black car', (700, 180, 960, 320)), ('12001', 'red car', (480, 180, 740, 320)))
        for fill in ('rays', 'learnt')]
canvas = Image.new('RGB', (2 * 520 + 3 * pad, 2 * (280 + title) + 3 * pad), 'white'); d = ImageDraw.Draw(canvas)
for i, (t, p) in enumerate(zoom):
    x, y = pad + (i % 2) * (520 + pad), pad + (i // 2) * (280 + title + pad)
    d.text((x, y), t, fill='black', font=font); canvas.paste(p, (x, y + title))
canvas.save(out.replace('.png', '_zoom.png'))
