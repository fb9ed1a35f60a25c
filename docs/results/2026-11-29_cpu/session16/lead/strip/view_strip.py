# ruff: noqa: E402, E501, E702, I001, B905
import torch
from PIL import Image, ImageDraw
import numpy as np
import sdn3d.editing.photo.road as road
d = torch.load('/tmp/s16data/lead/strip/ray_inputs.pt', weights_only=False)
a, k = d['args'], d['kwargs']
image, hole = a[0], a[1]
out, _ = road.ray_fill(*a, **k)
ys, xs = hole.nonzero(as_tuple=True)
lab = road.road_lab(out[:, ys, xs].T.contiguous())
yellow = (lab[:, 2] - k['road'][2] > 8)
box = (640, 170, 1000, 320)
def crop(t):
    arr = (t.permute(1, 2, 0).clamp(0, 1).numpy() * 255).astype(np.uint8)
    return Image.fromarray(arr).crop(box)
inp = image.clone(); inp[:, hole] = inp[:, hole] * 0.5 + torch.tensor([0., 0., 0.5])[:, None]
mk = out.clone(); mk[:, ys[yellow], xs[yellow]] = torch.tensor([1., 0., 1.])[:, None]
tiles = [('input, hole tinted blue', crop(inp)), ('rays fill', crop(out)), ('yellow fill px (magenta)', crop(mk))]
s = 3; w, h = tiles[0][1].size
img = Image.new('RGB', (w * s, (h * s + 16) * 3), 'white'); dr = ImageDraw.Draw(img)
for i, (n, t) in enumerate(tiles):
    img.paste(t.resize((w * s, h * s), Image.NEAREST), (0, i * (h * s + 16) + 16)); dr.text((4, i * (h * s + 16) + 2), n, fill='black')
img.save('/tmp/s16data/lead/strip/strip_view.png')
