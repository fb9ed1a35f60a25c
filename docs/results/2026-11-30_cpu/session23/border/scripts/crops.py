"""crops.py OUT.png TITLE TREE:FRAME:ID:LABEL...: a grid of photo crops of ground-truth cars (the tree's RGB frame at
its stored size, the car's ground-truth box at 312x96 scaled to it, with a margin), each titled with its label, for
looking at what the lamp cue reads. FRAME: 'vkitti1/0002/rain/00012'; ID: the instance id (class * 1000 + k)."""
import sys
from pathlib import Path

from PIL import Image, ImageDraw

from sdn3d.data.scene_gt import ground_truth
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.labels import INSTANCE_DIVISOR

out, title, items = sys.argv[1], sys.argv[2], sys.argv[3:]
tiles = []
cache: dict = {}
for item in items:
    tree, frame, iid, label = item.split(":", 3)
    if tree not in cache:
        cache[tree] = index_records(read_frames(tree))
    _, w, var, fr = frame.split("/")
    rec = cache[tree][(w, var, int(fr))]
    gt = ground_truth(rec, (312, 96))
    left, top, right, bottom = gt.boxes[int(iid) % INSTANCE_DIVISOR].tolist()
    photo = Image.open(rec.rgb_path).convert("RGB")
    s = photo.width / 312
    m = 0.15 * max(right - left, bottom - top)
    box = [max(0, (left - m) * s), max(0, (top - m) * s), min(photo.width, (right + 1 + m) * s),
           min(photo.height, (bottom + 1 + m) * s)]
    crop = photo.crop(tuple(int(v) for v in box))
    k = 200 / max(crop.width, crop.height)
    crop = crop.resize((max(1, int(crop.width * k)), max(1, int(crop.height * k))), Image.NEAREST)
    tile = Image.new("RGB", (220, 240), "white")
    tile.paste(crop, (10, 34))
    d = ImageDraw.Draw(tile)
    for j, line in enumerate([f"{w}/{var}/{fr} id {iid}", label][:2]):
        d.text((4, 2 + 14 * j), line[:36], fill="black")
    tiles.append(tile)
cols = min(5, len(tiles))
rows = (len(tiles) + cols - 1) // cols
sheet = Image.new("RGB", (220 * cols, 240 * rows + 24), "white")
ImageDraw.Draw(sheet).text((6, 6), title, fill="black")
for i, t in enumerate(tiles):
    sheet.paste(t, (220 * (i % cols), 24 + 240 * (i // cols)))
Path(out).parent.mkdir(parents=True, exist_ok=True)
sheet.save(out)
