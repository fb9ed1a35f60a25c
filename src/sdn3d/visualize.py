"""Turn label, depth, normal and pose maps into uint8 RGB pictures (for reports and TensorBoard).

The picture functions take torch tensors or numpy arrays and return ``(H, W, 3)`` uint8 numpy arrays;
:func:`colorize_labels` and :func:`colorize_instances` colour batches for TensorBoard grids and return
``(B, 3, H, W)`` float tensors in [0, 1].
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import torch
from torch import Tensor

from sdn3d.labels import IGNORE_INDEX, SemanticClass

__all__ = [
    "colorize_labels",
    "colorize_instances",
    "colorize_ids",
    "colorize_depth",
    "normals_to_rgb",
    "pose_to_rgb",
    "overlay_mask",
    "hstack_panels",
    "BOX_COLORS",
    "draw_boxes",
    "box_label_layout",
    "BoxLabelLayout",
]


def _numpy(x: torch.Tensor | np.ndarray) -> np.ndarray:
    if isinstance(x, torch.Tensor):
        return x.detach().cpu().numpy()
    return np.asarray(x)


def colorize_ids(ids: torch.Tensor | np.ndarray, background: tuple[int, int, int] = (0, 0, 0)) -> np.ndarray:
    """Stable pseudo-random colours for integer ids ``(H, W)``; ids <= 0 get ``background``.

    The colour of an id depends only on the id (a multiplicative hash), so the same
    instance has the same colour in every picture.
    """
    ids = _numpy(ids).astype(np.int64)
    hashed = (ids * 2654435761) & 0xFFFFFF
    rgb = np.stack([(hashed >> 16) & 255, (hashed >> 8) & 255, hashed & 255], -1)
    rgb = 64 + (rgb * 191) // 255  # keep colours away from black
    rgb[ids <= 0] = background
    return rgb.astype(np.uint8)


def colorize_depth(depth: torch.Tensor | np.ndarray, max_depth: float | None = None) -> np.ndarray:
    """Inverse-depth shading of a ``(H, W)`` metric depth map; empty (inf/<=0) pixels are black."""
    depth = _numpy(depth).astype(np.float64)
    valid = np.isfinite(depth) & (depth > 0)
    if not valid.any():
        return np.zeros((*depth.shape, 3), np.uint8)
    near = depth[valid].min()
    far = max_depth if max_depth is not None else depth[valid].max()
    inv = np.zeros_like(depth)
    inv[valid] = (1.0 / np.clip(depth[valid], near, None) - 1.0 / far) / max(1.0 / near - 1.0 / far, 1e-12)
    inv = np.clip(inv, 0.0, 1.0)
    # a warm-to-cold ramp: near is bright yellow, far is dark blue
    rgb = np.stack([inv, inv**2, 0.4 * (1 - inv) + 0.1], -1)
    rgb[~valid] = 0
    return (rgb * 255).astype(np.uint8)


def normals_to_rgb(normals: torch.Tensor | np.ndarray) -> np.ndarray:
    """Camera-frame unit normals ``(3, H, W)`` to RGB ``(n + 1) / 2``; zero normals are black."""
    n = _numpy(normals).astype(np.float64)
    rgb = (np.transpose(n, (1, 2, 0)) + 1.0) * 0.5
    rgb[np.abs(n).sum(0) == 0] = 0
    return (np.clip(rgb, 0, 1) * 255).astype(np.uint8)


def pose_to_rgb(pose: torch.Tensor | np.ndarray) -> np.ndarray:
    """One-hot pose map ``(K, H, W)`` to a hue wheel over the K bins; empty pixels black."""
    p = _numpy(pose)
    k = p.shape[0]
    filled = p.sum(0) > 0
    hue = p.argmax(0).astype(np.float64) / k
    # HSV -> RGB with full saturation and value
    h6 = hue * 6
    x = 1 - np.abs(np.mod(h6, 2) - 1)
    sector = np.floor(h6).astype(int) % 6
    zeros, ones = np.zeros_like(x), np.ones_like(x)
    table = [
        (ones, x, zeros),
        (x, ones, zeros),
        (zeros, ones, x),
        (zeros, x, ones),
        (x, zeros, ones),
        (ones, zeros, x),
    ]
    rgb = np.zeros((*hue.shape, 3))
    for s, (r, g, b) in enumerate(table):
        sel = sector == s
        rgb[sel] = np.stack([r[sel], g[sel], b[sel]], -1)
    rgb[~filled] = 0
    return (rgb * 255).astype(np.uint8)


def overlay_mask(
    image: np.ndarray, mask: torch.Tensor | np.ndarray, color: tuple[int, int, int], alpha: float = 0.5
) -> np.ndarray:
    """Blend ``color`` into ``image (H, W, 3) uint8`` where ``mask (H, W)`` is true (or weighted)."""
    m = _numpy(mask).astype(np.float64)
    if m.max(initial=0) > 1:
        raise ValueError("overlay_mask: mask must be boolean or in [0, 1]")
    w = (alpha * m)[..., None]
    out = image.astype(np.float64) * (1 - w) + np.asarray(color, np.float64) * w
    return np.clip(out, 0, 255).astype(np.uint8)


def hstack_panels(panels: list[np.ndarray], gap: int = 4) -> np.ndarray:
    """Place ``(H, W, 3)`` uint8 panels side by side with white gaps (heights must match)."""
    if not panels:
        raise ValueError("hstack_panels: no panels")
    height = panels[0].shape[0]
    if any(p.shape[0] != height for p in panels):
        raise ValueError(f"hstack_panels: panel heights differ: {[p.shape[0] for p in panels]}")
    spacer = np.full((height, gap, 3), 255, np.uint8)
    parts: list[np.ndarray] = []
    for i, panel in enumerate(panels):
        if i:
            parts.append(spacer)
        parts.append(panel)
    return np.concatenate(parts, 1)


def _title_size(height: int, width: int) -> int:
    """A title's font size for a panel: a twelfth of its smaller side, 11 to 22 px."""
    return int(min(22, max(11, round(min(height, width) / 12))))


def titled_panel(image: np.ndarray, title: str, font_size: int | None = None) -> np.ndarray:
    """``image (H, W, 3)`` uint8 under a white band carrying ``title`` (shrunk to fit the width, down to 9 px,
    then cut with an ellipsis): ``(H + band, W, 3)``. ``font_size`` None: a twelfth of the smaller side, 11-22 px."""
    from PIL import Image, ImageDraw

    height, width = image.shape[:2]
    size = int(font_size) if font_size else _title_size(height, width)
    draw = ImageDraw.Draw(Image.new("RGB", (1, 1)))
    text = title
    while True:
        font = _font(size)
        left, up, right, down = draw.textbbox((0, 0), text, font=font)
        if right - left <= width - 6 or (size <= 9 and len(text) <= 2):
            break
        if size > 9:
            size -= 1
        else:
            text = text[:-2] + "…"
    pad = max(2, size // 4)
    try:  # the font's line height, not this text's: every title of one size gets the same band
        ascent, descent = font.getmetrics()
    except AttributeError:  # the fixed bitmap font
        ascent, descent = down, 0
    band = ascent + descent + 2 * pad
    canvas = Image.new("RGB", (width, height + band), (255, 255, 255))
    canvas.paste(Image.fromarray(np.ascontiguousarray(image)), (0, band))
    ImageDraw.Draw(canvas).text((3 - left, pad), text, fill=(0, 0, 0), font=font)
    return np.asarray(canvas, dtype=np.uint8).copy()


def titled_row(panels: Sequence[tuple[str, np.ndarray]], gap: int = 4, font_size: int | None = None) -> np.ndarray:
    """Panels side by side (:func:`hstack_panels`), each under its title (:func:`titled_panel`, one font size for
    the row so the bands match)."""
    size = int(font_size) if font_size else _title_size(*panels[0][1].shape[:2])
    titled = [titled_panel(image, title, size) for title, image in panels]
    band = max(t.shape[0] for t in titled)
    titled = [np.concatenate([np.full((band - t.shape[0], t.shape[1], 3), 255, np.uint8), t], 0) for t in titled]
    return hstack_panels(titled, gap)


def colorize_labels(label: Tensor, classes: Sequence[SemanticClass], ignore_index: int = IGNORE_INDEX) -> Tensor:
    """``(B, H, W)`` class indices -> ``(B, 3, H, W)`` float in [0, 1], in the dataset's colours
    (``ignore_index`` and out-of-range values black)."""
    palette = torch.zeros(len(classes) + 1, 3, device=label.device)
    palette[:-1] = torch.tensor([c.color for c in classes], dtype=torch.float32, device=label.device) / 255.0
    idx = torch.where((label >= 0) & (label < len(classes)) & (label != ignore_index), label,
                      torch.full_like(label, len(classes)))
    return palette[idx].permute(0, 3, 1, 2)


def colorize_instances(instance: Tensor) -> Tensor:
    """``(B, H, W)`` instance ids -> ``(B, 3, H, W)`` float in [0, 1]: a colour per id (a multiplicative
    hash of the id, so an id keeps its colour across images), black where the id is <= 0."""
    ids = instance.long().clamp_min(0)
    mult = torch.tensor([97, 57, 151], device=instance.device)
    rgb = ((ids.unsqueeze(1) * mult.view(1, 3, 1, 1) + 31) % 200 + 55).float() / 255.0
    return torch.where(ids.unsqueeze(1) > 0, rgb, torch.zeros_like(rgb))


#: Distinct, saturated colours for boxes drawn over a photo (cycled by the box's index).
BOX_COLORS: tuple[tuple[int, int, int], ...] = (
    (255, 59, 48), (52, 199, 89), (0, 122, 255), (255, 204, 0), (175, 82, 222), (0, 199, 190),
    (255, 149, 0), (255, 45, 146), (162, 132, 94), (90, 200, 250), (128, 255, 0), (255, 255, 255))


def _font(size: int):  # noqa: ANN202 - a PIL font
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)  # scalable (Pillow >= 10.1 with FreeType)
    except (TypeError, OSError):  # older Pillow / no FreeType: the fixed bitmap font
        return ImageFont.load_default()


Rect = tuple[float, float, float, float]


def _overlaps(a: Rect, b: Rect) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


@dataclass(frozen=True)
class BoxLabelLayout:
    """Where :func:`draw_boxes` puts the labels, in the returned picture's pixels: rectangles ``(x0, y0, x1, y1)``,
    half-open (the drawn pixels are ``x0 <= x < x1``, ``y0 <= y < y1``).

    ``legend`` False: each box's label on a tag near the box (``tags``). True (the tags would overlap): a numbered
    marker at each box (``tags``: the markers; a marker away from its box has a ``leaders`` line to it) and the
    legend (number and label, ``entries``) in a band below the image. ``numbers[i]`` is box i's number.
    """

    size: tuple[int, int]  # (width, height) of the returned picture
    top: int  # the title band's height: the image's first row
    legend: bool
    font_size: int
    tags: tuple[tuple[int, Rect], ...]  # (box index, its tag or numbered marker)
    entries: tuple[tuple[int, Rect, str], ...] = ()  # (box index, legend entry, the label as drawn)
    swatches: tuple[tuple[int, Rect], ...] = ()  # (box index, the numbered marker inside its legend entry)
    leaders: tuple[tuple[int, Rect], ...] = ()  # (box index, line (x0, y0, x1, y1) from the box to its marker)
    numbers: dict[int, str] = field(default_factory=dict)
    marker_size: int = 0
    legend_size: int = 0

    def rectangles(self) -> list[Rect]:
        """Every label rectangle drawn: the tags or markers, then the legend's entries."""
        return [r for _, r in self.tags] + [r for _, r, _ in self.entries]


def _text_box(draw, text: str, font) -> tuple[float, float, float, float]:  # noqa: ANN001 - PIL objects
    return draw.textbbox((0, 0), text, font=font)


def _sizes(height: int, width: int, font_size: int | None) -> tuple[int, int, int]:
    """``(font size, line width, padding)`` of :func:`draw_boxes`' tags and title."""
    size = int(font_size) if font_size else max(12, round(min(height, width) / 15))
    return size, max(2, size // 7), max(2, size // 6)


def _place_tags(draw, boxes: Sequence[Sequence[float] | None], labels: Sequence[str], font, width: int,  # noqa: ANN001
                height: int, band: int, pad: int) -> tuple[list[tuple[int, Rect]], bool]:
    """Each box's tag: above the box, else inside it or below, away from the tags already placed. Returns the tags
    and whether every one found a free place."""
    placed: list[tuple[int, Rect]] = []
    free = True
    for i, (box, label) in enumerate(zip(boxes, labels, strict=True)):
        if box is None:
            continue
        x0, y0, _, y1 = (float(b) for b in box)
        top, bottom = y0 + band, y1 + band
        left, up, right, down = _text_box(draw, label, font)
        tw, th = right - left + 2 * pad, down - up + 2 * pad
        tx = min(max(0.0, x0), max(0.0, width - tw))
        low = band + height - th
        candidates = [top - th, top, bottom, bottom - th] + [top + k * th for k in range(1, 8)]
        spots = [(tx, min(max(band, ty), low)) for ty in candidates]
        spot = next((p for p in spots if not any(_overlaps((*p, p[0] + tw, p[1] + th), q) for _, q in placed)), None)
        free = free and spot is not None
        tx, ty = spot or spots[0]
        placed.append((i, (tx, ty, tx + tw, ty + th)))
    return placed, free


def _free_spot(size: tuple[float, float], anchors: Sequence[tuple[float, float]], area: Rect,
               taken: Sequence[Rect], step: float) -> tuple[float, float] | None:
    """The first of ``anchors`` (top-left corners), else the grid point of ``area`` nearest the first anchor, where a
    ``size`` rectangle lies inside ``area`` and overlaps none of ``taken`` (a gap of 1 px kept); None: nowhere."""
    w, h = size

    def fits(x: float, y: float) -> bool:
        inside = area[0] <= x and x + w <= area[2] and area[1] <= y and y + h <= area[3]
        return inside and not any(_overlaps((x - 1, y - 1, x + w + 1, y + h + 1), q) for q in taken)

    for x, y in anchors:
        if fits(x, y):
            return x, y
    ax, ay = anchors[0]
    xs = np.arange(area[0], area[2] - w + 1e-6, step)
    ys = np.arange(area[1], area[3] - h + 1e-6, step)
    if not len(xs) or not len(ys):
        return None
    gx, gy = np.meshgrid(xs, ys)
    order = np.argsort(((gx - ax) ** 2 + (gy - ay) ** 2).ravel(), kind="stable")
    for k in order:
        x, y = float(gx.ravel()[k]), float(gy.ravel()[k])
        if fits(x, y):
            return x, y
    return None


def box_label_layout(image_size: tuple[int, int], boxes: Sequence[Sequence[float] | None], labels: Sequence[str],
                     title: str | None = None, font_size: int | None = None,
                     points: Sequence[Sequence[float] | None] | None = None) -> BoxLabelLayout:
    """Where :func:`draw_boxes` puts the labels of ``boxes`` on an image of ``image_size (W, H)``
    (:class:`BoxLabelLayout`): a tag per box (the look for a few objects) while every tag finds a place that no
    other tag covers; otherwise a small numbered marker at each box (near it, on the image: a line leads to one
    placed away from it; below the image where the image has no room left) and a legend of numbers and labels in
    columns in a band below the image. No two of its label rectangles overlap, whatever the number of boxes; the
    markers keep clear of the crosses at ``points`` (image pixels, as :func:`draw_boxes` takes them) too."""
    from PIL import Image, ImageDraw

    width, height = int(image_size[0]), int(image_size[1])
    if len(boxes) != len(labels):
        raise ValueError(f"draw_boxes: {len(boxes)} boxes and {len(labels)} labels")
    size, line, pad = _sizes(height, width, font_size)
    band = size + 2 * pad if title else 0
    draw = ImageDraw.Draw(Image.new("RGB", (1, 1)))
    tags, free = _place_tags(draw, boxes, labels, _font(size), width, height, band, pad)
    if free:
        return BoxLabelLayout((width, height + band), band, False, size, tuple(tags))
    # Numbered markers at the boxes, a legend below.
    msize = max(10, round(size * 0.6))
    lsize = max(11, round(size * 0.75))
    mfont, lfont = _font(msize), _font(lsize)
    mpad = max(2, msize // 5)
    drawn = [i for i, box in enumerate(boxes) if box is not None]
    numbers = {i: str(i + 1) for i in drawn}
    _, mup, _, mdown = _text_box(draw, "0123456789", mfont)
    mh = mdown - mup + 2 * mpad
    markers: list[tuple[int, Rect]] = []
    leaders: list[tuple[int, Rect]] = []
    overflow: list[tuple[int, float]] = []
    image_area = (0.0, float(band), float(width), float(band + height))
    reach = max(3, size // 3) + line  # a cross's half size and its outline
    centres = [(float(p[0]), float(p[1]) + band) for p in (points or ()) if p is not None]
    crosses = [(u - reach, v - reach, u + reach + 1, v + reach + 1) for u, v in centres]
    for i in drawn:
        left, _, right, _ = _text_box(draw, numbers[i], mfont)
        mw = max(mh, right - left + 2 * mpad)
        x0, y0, x1, y1 = (float(b) for b in boxes[i])
        y0, y1 = y0 + band, y1 + band
        anchors = [(x0, y0 - mh), (x0, y0), (x1 - mw, y0), (x0, y1), (x1 - mw, y0 - mh), (x0, y1 - mh),
                   (x1, y0), (x0 - mw, y0)]
        spot = _free_spot((mw, mh), anchors, image_area, [r for _, r in markers] + crosses, max(2.0, mh / 3))
        if spot is None:
            overflow.append((i, mw))
            continue
        rect = (spot[0], spot[1], spot[0] + mw, spot[1] + mh)
        markers.append((i, rect))
        box = (x0 - 1, y0 - 1, x1 + 1, y1 + 1)
        if not _overlaps(rect, box):  # away from its box: a line from the box's nearest point to the marker
            cx, cy = (rect[0] + rect[2]) / 2, (rect[1] + rect[3]) / 2
            leaders.append((i, (min(max(cx, x0), x1 - 1), min(max(cy, y0), y1 - 1), cx, cy)))
    bottom = band + height
    if overflow:  # no room left on the image: a row (or more) of markers below it, each with its line
        gap = max(2, mpad)
        x, y = float(pad), float(bottom + gap)
        for i, mw in overflow:
            if x + mw > width - pad and x > pad:
                x, y = float(pad), y + mh + gap
            rect = (x, y, x + mw, y + mh)
            markers.append((i, rect))
            x0, y0, x1, y1 = (float(b) for b in boxes[i])
            cx = (rect[0] + rect[2]) / 2
            leaders.append((i, (min(max(cx, x0), x1 - 1), y1 - 1 + band, cx, rect[1])))
            x += mw + gap
        bottom = int(np.ceil(y + mh))
    # The legend: entries "marker label" in columns, numbered in reading order down each column.
    gap = max(3, lsize // 3)
    _, lup, _, ldown = _text_box(draw, "Ag0", lfont)
    entry_h = max(mh, ldown - lup) + 2
    swatch = {i: max(mh, _text_box(draw, numbers[i], mfont)[2] - _text_box(draw, numbers[i], mfont)[0] + 2 * mpad)
              for i in drawn}
    room = max(1, width - 2 * pad)

    def fitted(i: int) -> str:
        text = labels[i]
        limit = room - swatch[i] - gap
        while text and _text_box(draw, text, lfont)[2] - _text_box(draw, text, lfont)[0] > limit:
            text = text[:-2] + "…" if len(text) > 2 else ""
        return text

    texts = {i: fitted(i) for i in drawn}
    widths = {i: swatch[i] + gap + (_text_box(draw, texts[i], lfont)[2] - _text_box(draw, texts[i], lfont)[0])
              for i in drawn}
    column = max(widths.values(), default=0) + 2 * gap
    columns = max(1, min(len(drawn), int((room + 2 * gap) // max(1, column)))) if drawn else 1
    rows = -(-len(drawn) // columns) if drawn else 0
    top = bottom + pad
    entries, swatches = [], []
    for k, i in enumerate(drawn):
        c, r = divmod(k, rows)
        x, y = float(pad + c * column), float(top + r * (entry_h + 2))
        entries.append((i, (x, y, x + widths[i], y + entry_h), texts[i]))
        swatches.append((i, (x, y + (entry_h - mh) / 2, x + swatch[i], y + (entry_h + mh) / 2)))
    total = top + rows * (entry_h + 2) + pad
    return BoxLabelLayout((width, int(total)), band, True, size, tuple(markers), tuple(entries), tuple(swatches),
                          tuple(leaders), numbers, msize, lsize)


def _marker(draw, rect: Rect, number: str, color: tuple[int, int, int], font) -> None:  # noqa: ANN001
    """A numbered marker: ``rect`` filled in ``color`` with a dark outline, the number centred."""
    draw.rectangle((rect[0], rect[1], rect[2] - 1, rect[3] - 1), fill=color, outline=(0, 0, 0), width=1)
    left, up, right, down = _text_box(draw, number, font)
    dark = 0.299 * color[0] + 0.587 * color[1] + 0.114 * color[2] < 150
    x = (rect[0] + rect[2] - (right - left)) / 2 - left
    y = (rect[1] + rect[3] - (down - up)) / 2 - up
    draw.text((x, y), number, fill=(255, 255, 255) if dark else (0, 0, 0), font=font)


def draw_boxes(image: np.ndarray, boxes: Sequence[Sequence[float] | None], labels: Sequence[str],
               title: str | None = None, font_size: int | None = None,
               points: Sequence[Sequence[float] | None] | None = None,
               masks: Sequence[np.ndarray | None] | None = None) -> np.ndarray:
    """``image (H, W, 3)`` uint8 with each box ``(x0, y0, x1, y1)`` (half-open pixels; None: not drawn)
    outlined in its own colour (:data:`BOX_COLORS`, by index) and its label on a filled tag (placed above
    the box, else inside it or below, away from the tags already placed); ``points[i]`` ``(u, v)`` (pixel
    centres at integers), if given, is marked with a cross in box i's colour; ``title`` goes on a white band
    above the image. Returns a new ``(H + band, W, 3)`` uint8 array.

    When the tags would overlap (many objects), each box gets a small numbered marker instead (its number is its
    index + 1; a line leads to a marker placed away from its box) and a legend in a white band below the image
    lists number and label: ``(H + band + legend, W, 3)``. :func:`box_label_layout` says where every label goes;
    no two of them overlap.

    ``masks[i]`` ``(H, W)`` bool, if given and not None, tints box i's pixels in its colour (45 %).

    ``font_size`` None: about a fifteenth of the image's smaller side, at least 12 px.
    """
    from PIL import Image, ImageDraw

    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ValueError(f"draw_boxes: image must be (H, W, 3) uint8, got {image.shape} {image.dtype}")
    if masks is not None:
        if len(masks) != len(boxes):
            raise ValueError(f"draw_boxes: {len(boxes)} boxes and {len(masks)} masks")
        image = image.copy()
        for i, mask in enumerate(masks):
            if mask is not None:
                color = np.array(BOX_COLORS[i % len(BOX_COLORS)], dtype=np.float32)
                image[mask] = (image[mask] * 0.55 + color * 0.45 + 0.5).astype(np.uint8)
    points = list(points) if points is not None else [None] * len(boxes)
    if not len(boxes) == len(labels) == len(points):
        raise ValueError(f"draw_boxes: {len(boxes)} boxes, {len(labels)} labels and {len(points)} points")
    height, width = image.shape[:2]
    size, line, pad = _sizes(height, width, font_size)
    layout = box_label_layout((width, height), boxes, labels, title, font_size, points)
    band = layout.top
    font = _font(size)
    canvas = Image.new("RGB", layout.size, (255, 255, 255))
    canvas.paste(Image.fromarray(np.ascontiguousarray(image)), (0, band))
    draw = ImageDraw.Draw(canvas)
    if title:
        draw.text((pad, pad), title, fill=(0, 0, 0), font=font)
    for i, box in enumerate(boxes):
        if box is not None:
            x0, y0, x1, y1 = (float(b) for b in box)
            draw.rectangle((x0, y0 + band, max(x0, x1 - 1), max(y0, y1 - 1) + band), outline=BOX_COLORS[
                i % len(BOX_COLORS)], width=line)
    if not layout.legend:  # tags after all boxes, so no box line crosses a label
        for i, (tx, ty, tx1, ty1) in layout.tags:
            color = BOX_COLORS[i % len(BOX_COLORS)]
            left, up, _, _ = _text_box(draw, labels[i], font)
            draw.rectangle((tx, ty, tx1, ty1), fill=color)
            dark = 0.299 * color[0] + 0.587 * color[1] + 0.114 * color[2] < 150
            draw.text((tx + pad - left, ty + pad - up), labels[i], fill=(255, 255, 255) if dark else (0, 0, 0),
                      font=font)
    else:
        mfont, lfont = _font(layout.marker_size), _font(layout.legend_size)
        thin = max(1, line // 2)
        for i, segment in layout.leaders:
            color = BOX_COLORS[i % len(BOX_COLORS)]
            draw.line(segment, fill=(0, 0, 0), width=thin + 2)
            draw.line(segment, fill=color, width=thin)
        for i, rect in layout.tags:
            _marker(draw, rect, layout.numbers[i], BOX_COLORS[i % len(BOX_COLORS)], mfont)
        gap = max(3, layout.legend_size // 3)
        for (i, (_, ey, _, ey1), text), (_, swatch) in zip(layout.entries, layout.swatches, strict=True):
            _marker(draw, swatch, layout.numbers[i], BOX_COLORS[i % len(BOX_COLORS)], mfont)
            tleft, tup, _, tdown = _text_box(draw, text, lfont)
            draw.text((swatch[2] + gap - tleft, (ey + ey1 - (tdown - tup)) / 2 - tup), text, fill=(0, 0, 0),
                      font=lfont)
    for i, point in enumerate(points):  # crosses last: always visible
        if point is not None:
            u, v, r = float(point[0]), float(point[1]) + band, max(3, size // 3)
            for color, w in (((0, 0, 0), line + 2), (BOX_COLORS[i % len(BOX_COLORS)], line)):
                draw.line((u - r, v, u + r, v), fill=color, width=w)
                draw.line((u, v - r, u, v + r), fill=color, width=w)
    return np.asarray(canvas, dtype=np.uint8).copy()
