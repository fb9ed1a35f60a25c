"""Issue 28, every figure labelled: ``objects.png`` (:func:`sdn3d.visualize.draw_boxes`) stays readable with 40
objects.

Before: each box's label went on a tag near the box, and past about ten objects the tags overlapped (a tag with no
free place was drawn over the others). Now: while every tag finds a free place the picture is as before; otherwise
each box gets a small numbered marker (clear of the other markers and of the 3D-centre crosses; a line leads to one
placed away from its box) and a legend of numbers and labels fills a band below the image. No two label rectangles
overlap (:func:`sdn3d.visualize.box_label_layout` says where each one is).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from sdn3d.visualize import BOX_COLORS, box_label_layout, draw_boxes

FRAME = Path(__file__).resolve().parent / "data" / "0006_30-deg-right_00043.png"
TITLE = "frame: id + class; + = projected 3D centre"


def _street(n: int, seed: int = 0, size: tuple[int, int] = (1242, 375)):
    """``n`` boxes crowded along the road of a ``size`` frame (as a street's cars are), their labels and centres."""
    rng = np.random.default_rng(seed)
    width, height = size
    boxes, labels = [], []
    for k in range(n):
        cx, cy = rng.uniform(0.04, 0.96) * width, rng.uniform(0.45, 0.7) * height
        w = rng.uniform(0.02, 0.16) * width
        h = w * rng.uniform(0.5, 0.8)
        boxes.append([max(0.0, cx - w / 2), max(0.0, cy - h / 2), min(width, cx + w / 2), min(height, cy + h / 2)])
        labels.append(f"{12000 + k} Car" + (f" fit {rng.uniform(0.4, 0.95):.2f}" if k % 3 == 0 else ""))
    points = [[(b[0] + b[2]) / 2, (b[1] + b[3]) / 2] for b in boxes]
    return boxes, labels, points


def _overlapping(rects) -> list[tuple[int, int]]:
    return [(i, j) for i, a in enumerate(rects) for j, b in enumerate(rects[i + 1:], i + 1)
            if a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]]


def _inside(rect, size) -> bool:
    return 0 <= rect[0] < rect[2] <= size[0] and 0 <= rect[1] < rect[3] <= size[1]


def test_forty_objects_get_numbered_markers_and_a_legend_without_overlaps(tmp_path):
    image = np.asarray(Image.open(FRAME).convert("RGB"))
    boxes, labels, points = _street(40)
    layout = box_label_layout((1242, 375), boxes, labels, TITLE, points=points)
    assert layout.legend and len(layout.tags) == 40 and len(layout.entries) == 40
    rects = layout.rectangles()
    assert _overlapping(rects) == [] and all(_inside(r, layout.size) for r in rects)
    # every marker on the image, clear of the crosses; each touches its box or has a line leading to it
    reach = max(3, layout.font_size // 3) + max(2, layout.font_size // 7)
    crosses = [(u - reach, v + layout.top - reach, u + reach + 1, v + layout.top + reach + 1) for u, v in points]
    led = {i for i, _ in layout.leaders}
    for i, marker in layout.tags:
        assert layout.top <= marker[1] and marker[3] <= layout.top + 375
        assert not any(pair[0] == 0 for pair in _overlapping([marker, *crosses])), i
        x0, y0, x1, y1 = boxes[i]
        box = (x0 - 1, y0 + layout.top - 1, x1 + 1, y1 + layout.top + 1)
        assert i in led or _overlapping([marker, box]), i
    # the legend: below the image, every label whole, in the order of the numbers
    assert all(r[1] >= layout.top + 375 for _, r, _ in layout.entries)
    assert [text for _, _, text in layout.entries] == labels
    assert [layout.numbers[i] for i, _, _ in layout.entries] == [str(k + 1) for k in range(40)]

    drawn = draw_boxes(image, boxes, labels, TITLE, points=points)
    assert drawn.shape == (layout.size[1], layout.size[0], 3) and drawn.shape[1] == 1242
    np.testing.assert_array_equal(drawn[layout.top:layout.top + 375][:5, :5], image[:5, :5])  # the photo, untouched
    for i, (x0, y0, x1, y1) in layout.swatches[:12]:  # each legend marker in its box's colour
        patch = drawn[int(np.ceil(y0)) + 1:int(y1) - 1, int(np.ceil(x0)) + 1:int(x1) - 1].reshape(-1, 3)
        assert (patch == BOX_COLORS[i % len(BOX_COLORS)]).all(1).mean() > 0.4, i
    Image.fromarray(drawn).save(tmp_path / "objects.png")


@pytest.mark.parametrize("seed", range(4))
def test_no_label_overlaps_whatever_the_crowd(seed):
    for n in (12, 25, 40, 60):
        boxes, labels, points = _street(n, seed)
        layout = box_label_layout((1242, 375), boxes, labels, TITLE, points=points)
        assert _overlapping(layout.rectangles()) == [], (n, seed)


def test_a_small_image_with_forty_objects_puts_the_markers_that_find_no_room_below_it():
    rng = np.random.default_rng(0)
    image = (rng.random((64, 160, 3)) * 255).astype(np.uint8)
    boxes, labels, points = _street(40, size=(160, 64))
    layout = box_label_layout((160, 64), boxes, labels, "tiny", points=points)
    rects = layout.rectangles()
    assert layout.legend and _overlapping(rects) == [] and all(_inside(r, layout.size) for r in rects)
    below = [i for i, r in layout.tags if r[1] >= layout.top + 64]
    assert below and {i for i, _ in layout.leaders} >= set(below)  # each with its line from the box
    drawn = draw_boxes(image, boxes, labels, "tiny", points=points)
    assert drawn.shape == (layout.size[1], 160, 3)


def test_a_label_wider_than_the_picture_is_shortened_in_the_legend():
    boxes, labels, points = _street(40, size=(300, 120))
    labels[3] = "12003 Car " + "very long label " * 10
    layout = box_label_layout((300, 120), boxes, labels, None, points=points)
    assert layout.legend and _overlapping(layout.rectangles()) == []
    text = {i: t for i, _, t in layout.entries}[3]
    assert text.endswith("…") and text.startswith("12003 Car") and len(text) < len(labels[3])
    assert all(_inside(r, layout.size) for r in layout.rectangles())


def test_a_few_objects_keep_their_tags_next_to_the_boxes():
    image = np.asarray(Image.open(FRAME).convert("RGB"))
    boxes = [[100, 200, 220, 280], [600, 180, 760, 300], None, [1000, 190, 1100, 260]]
    labels = ["12001 Car", "12002 Van", "12003 Car", "12004 Car fit 0.80"]
    layout = box_label_layout((1242, 375), boxes, labels, TITLE)
    assert not layout.legend and layout.entries == () and [i for i, _ in layout.tags] == [0, 1, 3]
    for i, tag in layout.tags:  # room above each box: the tag sits on its top edge
        assert tag[3] == pytest.approx(boxes[i][1] + layout.top) and tag[0] == pytest.approx(boxes[i][0])
    drawn = draw_boxes(image, boxes, labels, TITLE, points=[None] * 4)
    assert drawn.shape == (375 + layout.top, 1242, 3) and layout.size == (1242, 375 + layout.top)
    assert draw_boxes(image, boxes, labels).shape == image.shape  # no title: no band, nothing below
