"""Instance proposals without ground-truth masks: Panoptic-DeepLab centre / offset targets and grouping.

Training targets (:func:`panoptic_targets`) come from an instance map ``class_id * 1000 + k``:
every instance of a *thing* class (``SemanticClass.has_instances``, e.g. Car / Van) gets its
centre of mass; the centre heatmap is a Gaussian (``sigma`` pixels) at each rounded centre
(maximum where they overlap) and every pixel of the instance regresses the offset
``centre - pixel`` (``(du, dv)``, pixels). The heatmap is learnt with CenterNet's focal loss
(:func:`center_focal_loss`), the offsets with L1.

At inference (:func:`group_instances`) the heatmap's local maxima above a threshold are the
instance centres; each pixel predicted as a thing class votes for the centre nearest to
``pixel + offset``; an instance's class is the majority semantic class of its pixels.

Three inference rules make the proposals cover their vehicles, one each (measured on the demo's weights):

- **Which pixels are things** (:func:`thing_label`). The arg-max over all classes splits a vehicle's
  probability between Car and Van, and at a car's bottom rows, windows and edges the vehicle classes
  together often hold less than the best single stuff class (road, building): about a sixth of the
  vehicles' pixels are labelled as something else, and a proposal then covers only part of its car. A
  pixel is a thing pixel when the thing classes together hold at least ``thing_odds`` times the
  probability of the most probable stuff class; it takes its most probable thing class. ``thing_odds``
  below 1 leans towards vehicles because the grouping only joins a pixel to an instance whose centre its
  offset points at: a wrongly added pixel far from any vehicle still joins some instance, so the value is
  a trade-off, chosen on tuning data.
- **Two vehicles under one centre** (``split_separation``). Where one vehicle partly hides another, the
  heatmap often has one peak for both, while the hidden vehicle's offsets still point at a place of their
  own. An instance whose pixels' votes (``pixel + offset``) fall into two clusters is split in two: the
  votes are projected on their principal axis, divided by 1-D 2-means, and the instance is split when the
  clusters' means lie at least ``split_separation`` pooled standard deviations apart (each part at least
  ``min_area`` pixels). One cluster of votes spread evenly along a car gives 2-means a separation of
  2 sqrt(3) (about 3.5), a normal spread about 2.7, so the threshold sits above both.
- **Spatially separate parts that vote elsewhere** (``part_separation``). Where the heatmap has one peak above the
  threshold for two cars side by side (a real photo, whose heatmap is weaker than the synthetic frames' the branch
  learnt from), every vehicle pixel of both joins that one centre, and so do specks of vehicle pixels far away: one
  proposal over the whole picture. Such pixels are not connected to the instance's main part (its largest
  8-connected part), and their votes point elsewhere: a part whose votes' mean lies at least ``part_separation``
  pooled standard deviations from the main part's leaves the instance. It becomes an instance of its own when it has
  ``min_area`` sure pixels and its votes' mean lies inside its own bounding box (its votes name a centre on
  itself: the hidden car's offsets still point at its own centre); otherwise it is no instance's (a speck whose
  votes point at a neighbour). A car cut in two by a thin pole stays whole: both halves vote for one centre. The
  rule runs after the 2-means split, on each instance the split leaves: the split decides on the instance as
  grouped, specks and all (its threshold was chosen so); with far specks taken out first, the votes' spread along
  the principal axis shrinks and the split would cut cars it leaves whole.

Everything is batched: no Python loop over pixels or instances (only over chunks of pixels
when the pixel-to-centre distance matrix would be large).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.labels import INSTANCE_DIVISOR

__all__ = [
    "PanopticTargets",
    "thing_mask",
    "instance_segments",
    "center_heatmap",
    "panoptic_targets",
    "center_focal_loss",
    "find_centers",
    "thing_label",
    "group_instances",
    "group_vehicles",
]

# Pixel-to-centre distances are computed in chunks of at most this many (pixel, centre) pairs.
_CHUNK_PAIRS = 1 << 22
# Lloyd iterations of the 1-D 2-means that splits an instance's votes (it converges in a few on two clusters).
_SPLIT_ITERATIONS = 16
# Floor of a vote cluster's standard deviation (pixels): two tight clusters a pixel apart are not two vehicles.
_MIN_VOTE_SPREAD = 0.5


@dataclass
class PanopticTargets:
    """Training targets of the instance head.

    Attributes:
        center: ``(B, 1, H, W)`` Gaussian centre heatmap in [0, 1].
        offset: ``(B, 2, H, W)`` ``centre - pixel`` as ``(du, dv)`` on instance pixels, 0 elsewhere.
        offset_mask: ``(B, 1, H, W)`` bool, pixels of thing instances (where the offset loss applies).
    """

    center: Tensor
    offset: Tensor
    offset_mask: Tensor


def _class_lookup(thing_classes: Sequence[int] | Tensor, size: int, device: torch.device) -> Tensor:
    """``(size,)`` bool table: True at the thing class ids."""
    ids = torch.as_tensor(thing_classes, dtype=torch.long, device=device).flatten()
    table = torch.zeros(max(size, int(ids.max()) + 1 if ids.numel() else 1), dtype=torch.bool, device=device)
    table[ids] = True
    return table


def thing_mask(instance: Tensor, thing_classes: Sequence[int] | Tensor) -> Tensor:
    """``(B, H, W)`` bool: pixels of an instance (id > 0) whose class ``id // 1000`` is a thing class."""
    if instance.dtype not in (torch.int32, torch.int64):
        raise ValueError(f"instance must be an integer map, got dtype {instance.dtype}")
    cls = torch.div(instance, INSTANCE_DIVISOR, rounding_mode="floor").clamp_min(0)
    table = _class_lookup(thing_classes, int(cls.max()) + 1 if cls.numel() else 1, instance.device)
    return (instance > 0) & table[cls]


def instance_segments(instance: Tensor, mask: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """Segments of ``instance`` ``(B, H, W)`` restricted to ``mask`` ``(B, H, W)``.

    Returns:
        seg: ``(B, H, W)`` int64 segment index in ``[0, S)``, -1 outside ``mask``.
        batch: ``(S,)`` image index of each segment.
        ids: ``(S,)`` instance id of each segment.
    """
    b, h, w = instance.shape
    base = int(instance.max()) + 1 if instance.numel() else 1
    key = torch.arange(b, device=instance.device).view(b, 1, 1) * base + instance
    uniq, inverse = torch.unique(key[mask], return_inverse=True)
    seg = torch.full_like(instance, -1)
    seg[mask] = inverse
    return seg, torch.div(uniq, base, rounding_mode="floor"), uniq % base


def _segment_centroids(seg: Tensor, count: int) -> Tensor:
    """``(S, 2)`` centre of mass ``(u, v)`` of each segment of ``seg`` ``(B, H, W)``."""
    _, h, w = seg.shape
    v, u = torch.meshgrid(torch.arange(h, device=seg.device, dtype=torch.float32),
                          torch.arange(w, device=seg.device, dtype=torch.float32), indexing="ij")
    inside = seg >= 0
    idx = seg[inside]
    area = torch.bincount(idx, minlength=count).clamp_min(1).float()
    su = torch.bincount(idx, weights=u.expand_as(seg)[inside], minlength=count)
    sv = torch.bincount(idx, weights=v.expand_as(seg)[inside], minlength=count)
    return torch.stack([su / area, sv / area], dim=-1)


def center_heatmap(centers: Tensor, batch: Tensor, shape: tuple[int, int, int], sigma: float) -> Tensor:
    """``(B, 1, H, W)`` heatmap: max over Gaussians ``exp(-d^2 / (2 sigma^2))`` at the rounded ``centers``.

    Args:
        centers: ``(K, 2)`` ``(u, v)`` pixel coordinates.
        batch: ``(K,)`` image index of each centre.
        shape: ``(B, H, W)``.
        sigma: Gaussian standard deviation in pixels (truncated at 3 sigma).
    """
    if sigma <= 0:
        raise ValueError(f"sigma must be positive, got {sigma}")
    b, h, w = shape
    device = centers.device
    heat = torch.zeros(b * h * w, device=device)
    if centers.numel() == 0:
        return heat.view(b, 1, h, w)
    r = int(3 * sigma + 0.5)
    d = torch.arange(-r, r + 1, device=device)
    dv, du = torch.meshgrid(d, d, indexing="ij")
    g = torch.exp(-(du.float() ** 2 + dv.float() ** 2) / (2.0 * sigma**2))  # (P, P)
    c = centers.round().long()
    uu = c[:, 0].view(-1, 1, 1) + du  # (K, P, P)
    vv = c[:, 1].view(-1, 1, 1) + dv
    ok = (uu >= 0) & (uu < w) & (vv >= 0) & (vv < h)
    flat = (batch.view(-1, 1, 1) * h + vv) * w + uu
    heat.scatter_reduce_(0, flat[ok], g.expand_as(ok)[ok], reduce="amax")
    return heat.view(b, 1, h, w)


def panoptic_targets(instance: Tensor, thing_classes: Sequence[int] | Tensor, sigma: float = 4.0) -> PanopticTargets:
    """Centre heatmap and offset targets of the thing instances of ``instance`` ``(B, H, W)``."""
    if instance.dim() != 3:
        raise ValueError(f"instance must be (B, H, W), got {tuple(instance.shape)}")
    mask = thing_mask(instance, thing_classes)
    seg, batch, _ = instance_segments(instance, mask)
    centroids = _segment_centroids(seg, batch.numel())
    b, h, w = instance.shape
    v, u = torch.meshgrid(torch.arange(h, device=instance.device, dtype=torch.float32),
                          torch.arange(w, device=instance.device, dtype=torch.float32), indexing="ij")
    offset = torch.zeros(b, h, w, 2, device=instance.device)
    offset[mask] = centroids[seg[mask]] - torch.stack([u, v], -1).expand(b, h, w, 2)[mask]
    return PanopticTargets(
        center=center_heatmap(centroids, batch, (b, h, w), sigma),
        offset=offset.permute(0, 3, 1, 2).contiguous(),
        offset_mask=mask.unsqueeze(1),
    )


def center_focal_loss(logits: Tensor, target: Tensor, alpha: float = 2.0, beta: float = 4.0) -> Tensor:
    """CenterNet's penalty-reduced focal loss of centre-heatmap ``logits`` against a Gaussian ``target``.

    ``-(sum_peaks (1-p)^alpha log p + sum_others (1-t)^beta p^alpha log(1-p)) / #peaks`` with
    ``p = sigmoid(logits)``; peaks are the pixels where ``target == 1``. Used instead of
    Panoptic-DeepLab's 200x-weighted MSE: with plain SGD (the DRN recipe) that MSE diverges
    at lr 0.01, while the focal loss's gradients stay bounded.

    Args:
        logits, target: ``(B, 1, H, W)``.
    """
    if logits.shape != target.shape:
        raise ValueError(f"logits and target must have one shape, got {tuple(logits.shape)} and "
                         f"{tuple(target.shape)}")
    p = logits.sigmoid()
    peak = target >= 1.0
    pos = F.logsigmoid(logits) * (1.0 - p).pow(alpha)
    neg = F.logsigmoid(-logits) * p.pow(alpha) * (1.0 - target).pow(beta)
    loss = -torch.where(peak, pos, neg).sum()
    return loss / peak.sum().clamp_min(1)


def find_centers(center: Tensor, threshold: float = 0.1, nms_kernel: int = 7, top_k: int = 50
                 ) -> tuple[Tensor, Tensor, Tensor]:
    """Instance centres: local maxima of ``center`` ``(B, 1, H, W)`` above ``threshold``, best ``top_k`` per image.

    Returns:
        uv: ``(B, K, 2)`` pixel coordinates ``(u, v)``; scores: ``(B, K)``; valid: ``(B, K)`` bool
        (``K = min(top_k, H * W)``, ordered by decreasing score).
    """
    if center.dim() != 4 or center.shape[1] != 1:
        raise ValueError(f"center must be (B, 1, H, W), got {tuple(center.shape)}")
    if nms_kernel % 2 != 1:
        raise ValueError(f"nms_kernel must be odd, got {nms_kernel}")
    b, _, h, w = center.shape
    pooled = F.max_pool2d(center, nms_kernel, stride=1, padding=nms_kernel // 2)
    keep = (center == pooled) & (center > threshold)
    scores = torch.where(keep, center, torch.full_like(center, float("-inf"))).flatten(1)
    scores, idx = scores.topk(min(top_k, h * w), dim=1)
    uv = torch.stack([idx % w, torch.div(idx, w, rounding_mode="floor")], dim=-1).float()
    return uv, scores, torch.isfinite(scores)


def thing_label(probability: Tensor, thing_classes: Sequence[int] | Tensor, thing_odds: float | None) -> Tensor:
    """``(B, H, W)`` class map for the grouping: the arg-max class, except that a pixel whose thing classes together
    hold at least ``thing_odds`` times the probability of its most probable stuff class takes its most probable
    thing class (module doc). ``thing_odds`` None: the arg-max alone.

    Args:
        probability: ``(B, C, H, W)`` class probabilities (softmax).
        thing_classes: class ids of the things (ids in ``[0, C)``).
    """
    if probability.dim() != 4:
        raise ValueError(f"probability must be (B, C, H, W), got {tuple(probability.shape)}")
    label = probability.argmax(1)
    if thing_odds is None:
        return label
    if not thing_odds > 0:
        raise ValueError(f"thing_odds must be positive (or None), got {thing_odds}")
    ids = torch.as_tensor(thing_classes, dtype=torch.long, device=probability.device).flatten()
    if ids.numel() == 0:
        return label
    if int(ids.min()) < 0 or int(ids.max()) >= probability.shape[1]:
        raise ValueError(f"thing_classes {ids.tolist()} must be class ids below the {probability.shape[1]} classes")
    is_thing = torch.zeros(probability.shape[1], dtype=torch.bool, device=probability.device)
    is_thing[ids] = True
    if bool(is_thing.all()):
        return label
    things = probability[:, is_thing]
    stuff_best = probability[:, ~is_thing].amax(1)
    vehicle = things.sum(1) >= thing_odds * stuff_best
    return torch.where(vehicle, ids[things.argmax(1)], label)


def _split_parts(target: Tensor, slot: Tensor, slots: int, min_area: int, separation: float, sure: Tensor) -> Tensor:
    """``(N,)`` bool: the pixels that leave their slot for its second part (module doc, two vehicles under one
    centre). ``target`` ``(N, 2)``: each pixel's vote; ``slot`` ``(N,)`` in ``[0, slots)``: its instance; ``sure``
    ``(N,)`` bool: the pixels each part needs ``min_area`` of."""
    count = torch.bincount(slot, minlength=slots).to(target.dtype)
    n = count.clamp_min(1)
    mean = torch.stack([torch.bincount(slot, target[:, i], slots) for i in range(2)], -1) / n[:, None]
    d = target - mean[slot]
    sxx = torch.bincount(slot, d[:, 0] * d[:, 0], slots) / n
    syy = torch.bincount(slot, d[:, 1] * d[:, 1], slots) / n
    sxy = torch.bincount(slot, d[:, 0] * d[:, 1], slots) / n
    angle = 0.5 * torch.atan2(2 * sxy, sxx - syy)  # principal axis of each slot's 2x2 covariance
    s = d[:, 0] * angle.cos()[slot] + d[:, 1] * angle.sin()[slot]  # (N,) projection on it

    def halves(cut: Tensor) -> tuple[Tensor, Tensor, Tensor, Tensor, Tensor]:
        """Each pixel's side of its slot's ``cut`` (``high``), and each slot's counts and means of both sides."""
        high = s > cut[slot]
        n_hi = torch.bincount(slot, high.to(target.dtype), slots)
        n_lo = count - n_hi
        m_hi = torch.bincount(slot, s * high, slots) / n_hi.clamp_min(1)
        m_lo = torch.bincount(slot, s * ~high, slots) / n_lo.clamp_min(1)
        return high, n_hi, n_lo, m_hi, m_lo

    cut = torch.zeros(slots, dtype=target.dtype, device=target.device)  # the mean of the projections
    for _ in range(_SPLIT_ITERATIONS):  # 1-D 2-means of every slot at once
        _, n_hi, n_lo, m_hi, m_lo = halves(cut)
        cut = torch.where((n_hi > 0) & (n_lo > 0), (m_hi + m_lo) / 2, cut)
    high, n_hi, n_lo, m_hi, m_lo = halves(cut)
    r = s - torch.where(high, m_hi[slot], m_lo[slot])
    var_hi = torch.bincount(slot, r * r * high, slots) / n_hi.clamp_min(1)
    var_lo = torch.bincount(slot, r * r * ~high, slots) / n_lo.clamp_min(1)
    spread = ((var_hi + var_lo) / 2).sqrt().clamp_min(_MIN_VOTE_SPREAD)
    sure_hi = torch.bincount(slot, (sure & high).to(target.dtype), slots)
    sure_lo = torch.bincount(slot, (sure & ~high).to(target.dtype), slots)
    area = max(min_area, 1)
    split = ((m_hi - m_lo) / spread >= separation) & (sure_hi >= area) & (sure_lo >= area)
    return high & split[slot]


def _connected_parts(slot_map: Tensor) -> Tensor:
    """``(B, H, W)`` int64: each pixel's 8-connected component among the pixels of its own slot, named by the flat
    index (``(b * H + v) * W + u``) of the component's first pixel; ``B * H * W`` where ``slot_map`` is negative.

    Min-label propagation over the 8 neighbours of the same slot, each round followed by pointer jumping (a pixel
    takes its label's label), batched over the whole map until no label changes.
    """
    b, h, w = slot_map.shape
    n = b * h * w
    inside = slot_map >= 0
    root = torch.where(inside, torch.arange(n, device=slot_map.device).view(b, h, w), n)
    padded_slot = F.pad(slot_map, (1, 1, 1, 1), value=-1)
    flat_inside = inside.flatten()
    while True:
        padded_root = F.pad(root, (1, 1, 1, 1), value=n)
        best = root
        for dv, du in ((-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)):
            near = padded_root[:, 1 + dv:1 + dv + h, 1 + du:1 + du + w]
            same = padded_slot[:, 1 + dv:1 + dv + h, 1 + du:1 + du + w] == slot_map
            best = torch.minimum(best, torch.where(same & inside, near, n))
        flat = best.flatten().clone()
        flat[flat_inside] = flat[flat[flat_inside]]  # pointer jumping: labels only ever name pixels of the part
        jumped = flat.view(b, h, w)
        if torch.equal(jumped, root):
            return root
        root = jumped


def _separate_parts(target: Tensor, slot: Tensor, slots: int, pixel: Tensor, shape: tuple[int, int, int],
                    separation: float) -> tuple[Tensor, Tensor, Tensor]:
    """The spatially separate parts of each slot and which of them leave it (module doc). ``target`` ``(N, 2)``: each
    pixel's vote; ``slot`` ``(N,)`` in ``[0, slots)``; ``pixel`` ``(N,)``: each pixel's flat index
    ``(b * H + v) * W + u`` in a map of ``shape``.

    Returns:
        part: ``(N,)`` each pixel's part in ``[0, P)``; leaves: ``(P,)`` bool, the parts whose votes' mean lies
        ``separation`` pooled standard deviations from their slot's largest part's; centred: ``(P,)`` bool, the parts
        whose votes' mean lies inside their own bounding box (a centre of their own).
    """
    b, h, w = shape
    slot_map = torch.full((b * h * w,), -1, dtype=torch.long, device=slot.device)
    slot_map[pixel] = slot
    root = _connected_parts(slot_map.view(b, h, w)).flatten()[pixel]
    _, part = torch.unique(root, return_inverse=True)
    parts = int(part.max()) + 1
    part_slot = torch.zeros(parts, dtype=torch.long, device=slot.device).scatter_(0, part, slot)
    area = torch.bincount(part, minlength=parts)
    # Each slot's main part: its largest (ties: the first).
    largest = torch.zeros(slots, dtype=area.dtype, device=slot.device).scatter_reduce(0, part_slot, area, "amax")
    index = torch.arange(parts, device=slot.device)
    main = torch.full((slots,), parts, dtype=torch.long, device=slot.device).scatter_reduce(
        0, part_slot, torch.where(area == largest[part_slot], index, parts), "amin")[part_slot]
    n = area.clamp_min(1).to(target.dtype)
    mean = torch.stack([torch.bincount(part, target[:, i], parts) for i in range(2)], -1) / n[:, None]
    d = target - mean[part]
    var = torch.bincount(part, (d * d).sum(-1) / 2, parts) / n  # per axis, both axes pooled
    spread = ((var + var[main]) / 2).sqrt().clamp_min(_MIN_VOTE_SPREAD)
    leaves = (main != index) & ((mean - mean[main]).norm(dim=-1) / spread >= separation)
    where = torch.stack([pixel % w, torch.div(pixel, w, rounding_mode="floor") % h], -1).to(target.dtype)
    low = torch.full((parts, 2), float("inf"), dtype=target.dtype, device=slot.device)
    low = low.scatter_reduce(0, part[:, None].expand(-1, 2), where, "amin")
    high = torch.full_like(low, float("-inf")).scatter_reduce(0, part[:, None].expand(-1, 2), where, "amax")
    centred = ((mean >= low) & (mean <= high)).all(-1)
    return part, leaves, centred


def group_vehicles(label: Tensor, probability: Tensor, center: Tensor, offset: Tensor,
                   thing_classes: Sequence[int] | Tensor, thing_odds: float | None = None, threshold: float = 0.1,
                   nms_kernel: int = 7, top_k: int = 50, min_area: int = 0,
                   split_separation: float | None = None, part_separation: float | None = None
                   ) -> tuple[Tensor, Tensor]:
    """The grouping with the module doc's three inference rules, as the predictor and the training module's
    evaluation run it: the pixels :func:`thing_label` makes things (``thing_odds``) are grouped by
    :func:`group_instances`, whose ``min_area`` counts the arg-max ``label``'s thing pixels only (``sure``).

    Args:
        label: ``(B, H, W)`` the arg-max class map; probability: ``(B, C, H, W)`` its class probabilities.
        center, offset, thing_classes, threshold, nms_kernel, top_k, min_area, split_separation, part_separation:
            as :func:`group_instances`.

    Returns:
        instance: as :func:`group_instances`.
        label: ``label`` with each instance's pixels set to its majority class (a pixel only ``thing_odds`` made
        a thing keeps its arg-max class unless an instance took it).
    """
    sure = torch.isin(label, torch.as_tensor(thing_classes, device=label.device))
    instance, grouped = group_instances(thing_label(probability, thing_classes, thing_odds), center, offset,
                                        thing_classes, threshold=threshold, nms_kernel=nms_kernel, top_k=top_k,
                                        min_area=min_area, split_separation=split_separation, sure=sure,
                                        part_separation=part_separation)
    return instance, torch.where(instance > 0, grouped, label)


def group_instances(
    label: Tensor,
    center: Tensor,
    offset: Tensor,
    thing_classes: Sequence[int] | Tensor,
    threshold: float = 0.1,
    nms_kernel: int = 7,
    top_k: int = 50,
    min_area: int = 0,
    split_separation: float | None = None,
    sure: Tensor | None = None,
    part_separation: float | None = None,
) -> tuple[Tensor, Tensor]:
    """Split the thing pixels of a semantic map into instances (Panoptic-DeepLab grouping).

    Args:
        label: ``(B, H, W)`` predicted semantic classes.
        center: ``(B, 1, H, W)`` predicted centre heatmap.
        offset: ``(B, 2, H, W)`` predicted offsets ``(du, dv)``.
        thing_classes: class ids split into instances.
        threshold, nms_kernel, top_k: centre detection (:func:`find_centers`).
        min_area: instances with fewer pixels are dropped (their pixels get no instance); with ``sure``, fewer of
            those pixels.
        split_separation: an instance whose votes form two clusters this many pooled standard deviations apart is
            split in two (module doc); None: never split.
        sure: ``(B, H, W)`` bool, optional: the pixels ``min_area`` counts (an instance's, and each part's of a
            split); None: every thing pixel. :func:`thing_label`'s callers pass the arg-max's thing pixels, so that
            the pixels ``thing_odds`` adds widen the instances the arg-max has without making new ones.
        part_separation: an instance's spatially separate part (8-connected) whose votes' mean lies this many pooled
            standard deviations from its largest part's leaves the instance: its own instance with ``min_area``
            (``sure``) pixels, else no instance's (module doc); None: instances keep all their pixels.

    Returns:
        instance: ``(B, H, W)`` int64 ``class_id * 1000 + k`` (``k`` = 1 + rank of the centre's score; the second
        part of a split instance ``K + k``, ``K = min(top_k, H * W)``; a part that left its instance ``2K + 1 + j``,
        ``j`` its rank by area among its image's), 0 where there is no instance.
        label: ``(B, H, W)`` the semantic map with each instance's pixels set to its majority class.
    """
    if label.dim() != 3 or center.shape[-2:] != label.shape[-2:] or offset.shape[-2:] != label.shape[-2:]:
        raise ValueError(f"label (B, H, W), center (B, 1, H, W) and offset (B, 2, H, W) must agree; got "
                         f"{tuple(label.shape)}, {tuple(center.shape)}, {tuple(offset.shape)}")
    if sure is not None and (sure.shape != label.shape or sure.dtype != torch.bool):
        raise ValueError(f"sure must be a bool map of label's shape {tuple(label.shape)}, got {tuple(sure.shape)} "
                         f"{sure.dtype}")
    b, h, w = label.shape
    device = label.device
    num_classes = max(int(label.max()) + 1 if label.numel() else 1,
                      int(torch.as_tensor(thing_classes).max()) + 1 if len(thing_classes) else 1)
    is_thing = _class_lookup(thing_classes, num_classes, device)[label.clamp(0, num_classes - 1)]
    uv, _, valid = find_centers(center, threshold, nms_kernel, top_k)
    k = uv.shape[1]
    instance = torch.zeros_like(label)
    pix_b, pix_v, pix_u = torch.nonzero(is_thing & valid.any(1).view(b, 1, 1), as_tuple=True)
    if pix_b.numel() == 0 or k == 0:
        return instance, label
    target = torch.stack([pix_u.float() + offset[pix_b, 0, pix_v, pix_u],
                          pix_v.float() + offset[pix_b, 1, pix_v, pix_u]], dim=-1)  # (N, 2)
    nearest = torch.empty_like(pix_b)
    chunk = max(1, _CHUNK_PAIRS // k)
    for start in range(0, pix_b.numel(), chunk):  # bounded memory: chunks of pixels, not one loop per pixel
        sl = slice(start, start + chunk)
        d2 = (target[sl, None, :] - uv[pix_b[sl]]).pow(2).sum(-1)  # (n, K)
        d2 = d2.masked_fill(~valid[pix_b[sl]], float("inf"))
        nearest[sl] = d2.argmin(1)
    # Each (image, centre) is a slot; a split slot's second part is the slot b * k more; a part that left its slot
    # for an instance of its own is a slot after those 2 b k.
    slot = pix_b * k + nearest
    counted = torch.ones_like(pix_b, dtype=torch.bool) if sure is None else sure[pix_b, pix_v, pix_u]
    if split_separation is not None and not split_separation > 0:
        raise ValueError(f"split_separation must be positive (or None), got {split_separation}")
    if part_separation is not None and not part_separation > 0:
        raise ValueError(f"part_separation must be positive (or None), got {part_separation}")
    if split_separation is not None:  # decided on the instance as grouped, far specks and all (module doc)
        second = _split_parts(target, slot, b * k, min_area, split_separation, counted)
        slot = slot + second * (b * k)
        nearest = nearest + second * k
    assigned = torch.ones_like(counted)  # False: the pixel left its slot and belongs to no instance
    pieces = 0
    if part_separation is not None:  # on each instance the split left
        part, leaves, centred = _separate_parts(target, slot, 2 * b * k, (pix_b * h + pix_v) * w + pix_u, (b, h, w),
                                                part_separation)
        parts = leaves.numel()
        own = leaves & centred & (torch.bincount(part[counted], minlength=parts) >= max(min_area, 1))
        # A leaving part with min_area becomes an instance: k after the 2K of the centres and their second parts,
        # numbered per image by decreasing area; one beyond the ids an image has is dropped like a speck.
        part_image = torch.zeros(parts, dtype=torch.long, device=device).scatter_(0, part, pix_b)
        area = torch.bincount(part, minlength=parts)
        mine = own.nonzero()[:, 0]
        mine = mine[torch.argsort(part_image[mine] * (h * w + 1) + (h * w - area[mine]), stable=True)]
        image_of = part_image[mine]
        rank = torch.arange(mine.numel(), device=device) - torch.searchsorted(image_of, image_of)
        fits = 2 * k + rank + 1 < INSTANCE_DIVISOR
        pieces = int(fits.sum())
        part_slot = torch.full((parts,), -1, dtype=torch.long, device=device)
        part_slot[mine[fits]] = 2 * b * k + torch.arange(pieces, device=device)
        part_k = torch.zeros(parts, dtype=torch.long, device=device)
        part_k[mine[fits]] = 2 * k + rank[fits]
        moved = part_slot[part] >= 0
        assigned = ~leaves[part] | moved
        slot = torch.where(moved, part_slot[part], slot)
        nearest = torch.where(moved, part_k[part], nearest)
    slots = 2 * b * k + pieces
    # Majority class per slot, then area filter.
    cls = label[pix_b, pix_v, pix_u]
    votes = torch.bincount((slot * num_classes + cls)[assigned], minlength=slots * num_classes).view(slots,
                                                                                                      num_classes)
    voted = votes.argmax(1)
    keep = torch.bincount(slot[counted & assigned], minlength=slots) >= max(min_area, 1)
    kept = keep[slot] & assigned
    ids = voted[slot] * INSTANCE_DIVISOR + nearest + 1
    instance[pix_b[kept], pix_v[kept], pix_u[kept]] = ids[kept]
    label = label.clone()
    label[pix_b[kept], pix_v[kept], pix_u[kept]] = voted[slot][kept]
    return instance, label
