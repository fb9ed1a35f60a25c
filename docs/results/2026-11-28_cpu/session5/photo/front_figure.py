# ruff: noqa: E402, E501
"""A labelled figure of photo.keep_in_front on the unit tests' scene (a car with a dark pole in front of it, the pole
cut out of its mask): input, deleted and moved, with the setting off and on.   python front_figure.py OUT.png"""
import dataclasses
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

sys.path.insert(0, str(Path(__file__).resolve().parents[5]))
from sdn3d.editing.apply import Delete, Move, apply_edits
from sdn3d.editing.photo.transfer import render_photo
from tests.test_photo import FRAME, NO_LIGHT
from tests.test_photo_occluders import _pole_scene

scene, image, _ = _pole_scene()
panels = [("input: a pole in front of the car", image)]
for name, ops in (("deleted", [Delete(12001)]), ("moved left", [Move(12001, (20.0, 40.0))])):
    for keep in (False, True):
        settings = dataclasses.replace(NO_LIGHT, keep_in_front=keep)
        result = render_photo(image, FRAME, scene, apply_edits(scene, ops), settings=settings)
        panels.append((f"{name}, keep_in_front={str(keep).lower()}", result.image))
tiles = []
for title, picture in panels:
    arr = (picture.clamp(0, 1).permute(1, 2, 0).numpy() * 255).astype(np.uint8)
    tile = Image.fromarray(arr).resize((arr.shape[1] * 2, arr.shape[0] * 2), Image.NEAREST)
    canvas = Image.new("RGB", (tile.width, tile.height + 18), "white")
    canvas.paste(tile, (0, 18))
    ImageDraw.Draw(canvas).text((4, 3), title, fill="black")
    tiles.append(canvas)
out = Image.new("RGB", (tiles[0].width * 3 + 8, tiles[0].height * 2 + 4), "white")
for i, tile in enumerate([tiles[0], tiles[1], tiles[2], None, tiles[3], tiles[4]]):
    if tile is not None:
        out.paste(tile, ((i % 3) * (tile.width + 4), (i // 3) * (tile.height + 4)))
out.save(sys.argv[1])
