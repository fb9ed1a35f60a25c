"""Code-swap test: does an object's texture code decide its colour, and only its colour?

For pairs of objects A, B of one class in one frame whose colours differ (CIE76 ``Delta E >= min_delta_e``
between their mean colours in the real image), A is given B's code through the normal editing path
(:class:`~sdn3d.editing.apply.SetCode` on the de-rendered scene, :func:`~sdn3d.scene.maps.scene_maps`, the
textural generator) and compared with the reconstruction (the unedited scene drawn by the same generator).
Per pair, with colours the mean sRGB over A's region (the pixels the generator draws A's code into, eroded by
``erode`` pixels so boundary pixels that blend with the surroundings do not count):

- **colour move** ``m = (c_swap(A) - c_rec(A)) . (c_real(B) - c_real(A)) / |c_real(B) - c_real(A)|^2``: how far
  A's rendered colour moved along the way from A's real colour to B's (0 = no change, 1 = B's colour; it can
  overshoot or go negative). ``color_move_rendered`` uses the reconstruction's colours of A and B instead of
  the real ones (the move relative to what the generator itself draws for B).
- **off-axis change** ``|change - m (c_real(B) - c_real(A))| / |c_real(B) - c_real(A)|``: colour change that is not
  towards B.
- **silhouette change** ``1 - IoU(S_swap, S_rec)``: ``S`` is the set of pixels of A's window (its region's box
  grown by ``window_margin`` pixels) that read as A, not as its surroundings, in a render: nearest mean colour,
  with A's mean over its region and the surroundings' mean over the rest of the window, in that render. A code
  that only repaints A keeps ``S`` (0); one that also changes A's outline, or paints A into its surroundings,
  moves it. (The generator's input layout is the same in both renders, so the layout itself cannot be compared;
  this reads the outline off the pixels.) ``iou_swap_vs_region`` / ``iou_rec_vs_region``: ``S`` against A's region.
- **leak** ``mean |swap - rec|`` outside A's region grown by 2 pixels over ``mean |swap - rec|`` inside it:
  how much of the change falls on the rest of the image (per pixel).

:func:`code_swap_frame` runs one frame (batched over its pairs), :func:`summarize` averages over frames.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass

import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.editing.apply import SetCode, apply_edits
from sdn3d.scene.code import SceneCode
from sdn3d.scene.maps import ComposedMaps, scene_maps
from sdn3d.textural.codes import rgb_to_lab
from sdn3d.textural.renderer import TexturalRenderer

__all__ = ["CodeSwapSettings", "code_swap_frame", "color_move", "pair_metrics", "region_colors", "summarize",
           "swap_pairs"]

PAIR_METRICS = ("color_move", "color_move_rendered", "off_axis", "silhouette_change", "iou_swap_vs_region",
                "iou_rec_vs_region", "leak")


@dataclass(frozen=True)
class CodeSwapSettings:
    """Which pairs are tested and how (module doc).

    Attributes:
        min_pixels: smallest region (pixels at the working size, after erosion) of A and of B.
        min_delta_e: CIE76 distance between A's and B's real mean colours for the pair to count as "different
            colours".
        max_pairs_per_frame: at most this many pairs of a frame (a seeded random choice of the candidates).
        erode: pixels removed from a region's border before its mean colour is taken.
        window_margin: pixels A's window extends beyond its region's box (silhouette).
        batch_size: renders per generator call.
        seed: the pair choice.
    """

    min_pixels: int = 60
    min_delta_e: float = 20.0
    max_pairs_per_frame: int = 8
    erode: int = 1
    window_margin: int = 4
    batch_size: int = 16
    seed: int = 0


def _erode(masks: Tensor, pixels: int) -> Tensor:
    """``(N, H, W)`` bool masks shrunk by ``pixels`` (3x3 steps; the image border does not erode)."""
    if pixels <= 0:
        return masks
    k = 2 * pixels + 1
    return -F.max_pool2d(-masks[:, None].float(), k, 1, pixels)[:, 0] > 0.5


def _dilate(masks: Tensor, pixels: int) -> Tensor:
    if pixels <= 0:
        return masks
    return F.max_pool2d(masks[:, None].float(), 2 * pixels + 1, 1, pixels)[:, 0] > 0.5


def region_colors(images: Tensor, masks: Tensor) -> Tensor:
    """``(N, 3)`` mean colour of ``images (N, 3, H, W)`` (or one ``(3, H, W)`` for all) over ``masks (N, H, W)``."""
    if images.dim() == 3:
        images = images.expand(masks.shape[0], *images.shape)
    weights = masks.to(images.dtype)[:, None]
    return (images * weights).sum((2, 3)) / weights.sum((2, 3)).clamp_min(1)


def color_move(rec_a: Tensor, swap_a: Tensor, from_a: Tensor, to_b: Tensor) -> tuple[Tensor, Tensor]:
    """``(move (P,), off_axis (P,))`` of A's colour change ``swap_a - rec_a`` along ``to_b - from_a``
    (all ``(P, 3)``)."""
    step = to_b - from_a
    norm2 = (step * step).sum(1).clamp_min(1e-12)
    change = swap_a - rec_a
    move = (change * step).sum(1) / norm2
    off = (change - move[:, None] * step).norm(dim=1) / norm2.sqrt()
    return move, off


def swap_pairs(class_ids: Tensor, colors: Tensor, usable: Tensor, settings: CodeSwapSettings,
               generator: torch.Generator | None = None) -> Tensor:
    """``(P, 2)`` rows ``(a, b)``: ordered pairs of usable objects of one class whose colours ``(N, 3)`` differ by
    at least ``min_delta_e`` (CIE76), at most ``max_pairs_per_frame`` of them (seeded random choice)."""
    n = class_ids.numel()
    lab = rgb_to_lab(colors)
    apart = torch.cdist(lab, lab) >= settings.min_delta_e
    ok = apart & (class_ids[:, None] == class_ids[None]) & usable[:, None] & usable[None]
    ok &= ~torch.eye(n, dtype=torch.bool)
    pairs = torch.nonzero(ok)
    if pairs.shape[0] > settings.max_pairs_per_frame:
        pick = torch.randperm(pairs.shape[0], generator=generator)[: settings.max_pairs_per_frame]
        pairs = pairs[pick.sort().values]
    return pairs


def _silhouette(render: Tensor, region: Tensor, window: Tensor) -> Tensor:
    """``(P, H, W)`` pixels of ``window`` nearer (RGB) to the mean of ``render (P, 3, H, W)`` over ``region`` than to
    its mean over the rest of the window."""
    inside = region_colors(render, region & window)
    outside = region_colors(render, window & ~region)
    d_in = (render - inside[:, :, None, None]).norm(dim=1)
    d_out = (render - outside[:, :, None, None]).norm(dim=1)
    return window & (d_in < d_out)


def _iou(a: Tensor, b: Tensor) -> Tensor:
    return (a & b).flatten(1).sum(1) / (a | b).flatten(1).sum(1).clamp_min(1)


def _windows(regions: Tensor, margin: int) -> Tensor:
    """``(P, H, W)``: each region's box (half-open) grown by ``margin`` pixels, clipped to the image."""
    p, h, w = regions.shape
    rows, cols = regions.any(2), regions.any(1)
    ar_h, ar_w = torch.arange(h), torch.arange(w)
    big = torch.tensor(10**9)
    y0 = torch.where(rows, ar_h, big).min(1).values - margin
    y1 = torch.where(rows, ar_h, -big).max(1).values + margin
    x0 = torch.where(cols, ar_w, big).min(1).values - margin
    x1 = torch.where(cols, ar_w, -big).max(1).values + margin
    in_y = (ar_h[None] >= y0[:, None]) & (ar_h[None] <= y1[:, None])
    in_x = (ar_w[None] >= x0[:, None]) & (ar_w[None] <= x1[:, None])
    return in_y[:, :, None] & in_x[:, None, :]


def pair_metrics(rec: Tensor, swapped: Tensor, regions: Tensor, real_a: Tensor, real_b: Tensor, rec_b: Tensor,
                 settings: CodeSwapSettings) -> dict[str, Tensor]:
    """Per-pair metrics (module doc) of ``P`` pairs.

    Args:
        rec: ``(3, H, W)`` reconstruction; swapped: ``(P, 3, H, W)`` A drawn with B's code.
        regions: ``(P, H, W)`` bool, A's region in the generator's input.
        real_a, real_b: ``(P, 3)`` real mean colours of A and B; rec_b: ``(P, 3)`` B's colour in the reconstruction.
    """
    core = _erode(regions, settings.erode)
    rec_a, swap_a = region_colors(rec, core), region_colors(swapped, core)
    move, off = color_move(rec_a, swap_a, real_a, real_b)
    move_rendered, _ = color_move(rec_a, swap_a, rec_a, rec_b)
    window = _windows(regions, settings.window_margin)
    s_rec = _silhouette(rec.expand_as(swapped), regions, window)
    s_swap = _silhouette(swapped, regions, window)
    change = (swapped - rec).abs().mean(1)
    grown = _dilate(regions, 2)
    leak = region_colors(change[:, None], ~grown)[:, 0] / region_colors(change[:, None], regions)[:, 0].clamp_min(1e-6)
    return {"color_move": move, "color_move_rendered": move_rendered, "off_axis": off,
            "silhouette_change": 1 - _iou(s_swap, s_rec), "iou_swap_vs_region": _iou(s_swap, regions),
            "iou_rec_vs_region": _iou(s_rec, regions), "leak": leak}


def _render_batch(maps: Sequence[ComposedMaps], textural: TexturalRenderer, batch_size: int) -> Tensor:
    """``(P, 3, H, W)`` renders of composed maps, ``batch_size`` per generator call."""
    out = []
    dev = textural.device
    for start in range(0, len(maps), batch_size):
        chunk = maps[start:start + batch_size]

        def stack(name: str, chunk: Sequence[ComposedMaps] = chunk) -> Tensor:
            return torch.stack([getattr(m, name) for m in chunk]).to(dev)

        out.append(textural.render(stack("label"), stack("instance_label_map"), stack("boundary"),
                                   code_map=stack("feature"), pose=stack("pose"), normal=stack("normal")).cpu())
    return torch.cat(out).clamp(0, 1)


def code_swap_frame(scene: SceneCode, image: Tensor, textural: TexturalRenderer,
                    settings: CodeSwapSettings = CodeSwapSettings(),
                    generator: torch.Generator | None = None) -> dict[str, Tensor]:
    """The code-swap test on one frame: ``scene`` with its codes (``derender`` / ``encode_scene``) of
    ``image (3, H, W)`` in [0, 1].

    Returns:
        ``{'a', 'b'}``: ``(P,)`` instance ids; every name of :data:`PAIR_METRICS`: ``(P,)``.
    """
    bins = textural.spec.pose_bins
    base = scene_maps(scene, num_bins=bins)
    obj = scene.objects
    ids = obj.instance_id
    regions = base.instance_label_map[None].cpu() == ids[:, None, None]
    core = _erode(regions, settings.erode)
    real = region_colors(image.cpu().float(), core)
    things = torch.tensor([c.id for c in scene.class_list if c.has_instances])
    usable = (core.flatten(1).sum(1) >= settings.min_pixels) & torch.isin(obj.class_id, things)
    pairs = swap_pairs(obj.class_id, real, usable, settings, generator)
    empty = {"a": ids.new_zeros(0), "b": ids.new_zeros(0)} | {k: torch.zeros(0) for k in PAIR_METRICS}
    if pairs.shape[0] == 0:
        return empty
    a, b = pairs[:, 0], pairs[:, 1]
    edited = [scene_maps(apply_edits(scene, [SetCode(int(ids[i]), tuple(obj.code[j].tolist()))]), num_bins=bins)
              for i, j in pairs.tolist()]
    renders = _render_batch([base, *edited], textural, settings.batch_size)
    rec, swapped = renders[0], renders[1:]
    rec_colors = region_colors(rec, core)
    metrics = pair_metrics(rec, swapped, regions[a], real[a], real[b], rec_colors[b], settings)
    return {"a": ids[a], "b": ids[b], **metrics}


def summarize(frames: Sequence[dict[str, Tensor]], settings: CodeSwapSettings) -> dict:
    """Means (and medians) over every pair of every frame of :func:`code_swap_frame`'s results."""
    pairs = sum(int(f["a"].numel()) for f in frames)
    out: dict = {"pairs": pairs, "frames_with_pairs": sum(int(f["a"].numel() > 0) for f in frames),
                 "settings": asdict(settings)}
    for name in PAIR_METRICS:
        values = torch.cat([f[name].float() for f in frames]) if frames else torch.zeros(0)
        values = values[torch.isfinite(values)]
        out[name] = float(values.mean()) if values.numel() else math.nan
        out[f"{name}_median"] = float(values.median()) if values.numel() else math.nan
    return out
