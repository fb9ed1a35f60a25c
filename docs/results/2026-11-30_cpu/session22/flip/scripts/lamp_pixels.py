"""lamp_pixels.py OUT.png TITLE TREE:FRAME:ID:LABEL...: what the lamp cue reads on ground-truth cars (an oracle
mask): each car's photo crop (the frame as stored) beside the same crop with its mask's pixels that the red test
(red) and the headlights' test (cyan, lower half of the mask) take, read through the air as lamps.py does. An
approximation of the predictor's crops (the box, no margin or square resampling), for looking, not for measuring."""
import sys
from pathlib import Path

import torch
import torch.nn.functional as F
from PIL import Image, ImageDraw

from sdn3d.data.scene_gt import frame_photo, scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.lamps import LampCue, _red, through_the_air

out, title, items = sys.argv[1], sys.argv[2], sys.argv[3:]
cue = LampCue()
tiles, cache = [], {}
for item in items:
    tree, frame, iid, label = item.split(":", 3)
    if tree not in cache:
        cache[tree] = index_records(read_frames(tree))
    _, w, var, fr = frame.split("/")
    rec = cache[tree][(w, var, int(fr))]
    photo = frame_photo(rec, (312, 96)).image  # (3, H, W)
    objs = scene_from_frame(rec, (312, 96)).objects
    r = int((objs.instance_id == int(iid)).nonzero()[0])
    mask = F.interpolate(objs.mask[r][None, None].float(), size=photo.shape[-2:], mode="nearest")[0, 0] > 0.5
    ys, xs = mask.nonzero(as_tuple=True)
    top, bottom, left, right = int(ys.min()), int(ys.max()) + 1, int(xs.min()), int(xs.max()) + 1
    crop, m = photo[None, :, top:bottom, left:right], mask[None, top:bottom, left:right]
    seen = through_the_air(crop, m, cue.clear_dark)
    red = _red(seen, m, cue)[0]
    rows = torch.arange(m.shape[1])[:, None].expand(m.shape[1:])
    lower = rows * 2 > (int(rows[m[0]].min()) + int(rows[m[0]].max()))
    high, low = seen.amax(1)[0], seen.amin(1)[0]
    white = m[0] & lower & (low > cue.white_min) & (high - low < cue.white_spread)
    shown = crop[0].clone()
    shown[:, ~m[0]] *= 0.35
    marked = shown.clone()
    marked[:, red] = torch.tensor([1.0, 0.0, 0.0])[:, None]
    marked[:, white] = torch.tensor([0.0, 1.0, 1.0])[:, None]
    pair = torch.cat([shown, torch.ones(3, shown.shape[1], 2), marked], 2)
    img = Image.fromarray((pair.permute(1, 2, 0).clamp(0, 1) * 255).byte().numpy())
    k = min(420 / img.width, 180 / img.height)
    img = img.resize((max(1, int(img.width * k)), max(1, int(img.height * k))), Image.NEAREST)
    tile = Image.new("RGB", (430, 216), "white")
    tile.paste(img, (5, 32))
    d = ImageDraw.Draw(tile)
    d.text((4, 2), f"{w}/{var}/{fr} id {iid}: red {int(red.sum())} px, white {int(white.sum())} px "
                   f"of {int(m.sum())}", fill="black")
    d.text((4, 16), label[:70], fill="black")
    tiles.append(tile)
cols = min(3, len(tiles))
rows_n = (len(tiles) + cols - 1) // cols
sheet = Image.new("RGB", (430 * cols, 216 * rows_n + 24), "white")
ImageDraw.Draw(sheet).text((6, 6), title, fill="black")
for i, t in enumerate(tiles):
    sheet.paste(t, (430 * (i % cols), 24 + 216 * (i // cols)))
Path(out).parent.mkdir(parents=True, exist_ok=True)
sheet.save(out)
