"""Panoptic quality (Kirillov et al., CVPR 2019) of instance maps, per thing class, batched.

A predicted and a ground-truth segment of the same class match when their IoU exceeds 0.5
(matches are then unique). Per class::

    PQ = sum_TP IoU / (TP + FP / 2 + FN / 2) = SQ * RQ

As in the COCO / Cityscapes panoptic evaluation: pixels labelled ``ignore_index`` are void
(they count in neither area); a predicted segment that is not matched is no false positive
when more than half of it lies on void pixels or on "crowd" pixels of its class (pixels of
the class without an instance id, e.g. Cityscapes' ``cargroup``).

:func:`pq_stats` gives the sums of one batch (add them up over a dataset);
:func:`pq_from_stats` turns sums into PQ / SQ / RQ.
"""

from __future__ import annotations

from collections.abc import Sequence

import torch
from torch import Tensor

from sdn3d.labels import IGNORE_INDEX, INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import instance_segments

__all__ = ["pq_stats", "pq_from_stats"]


def _segments_of_things(instance: Tensor, position: Tensor, valid: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """Segments of thing instances on ``valid`` pixels: ``(seg (B,H,W), batch (S,), thing position (S,))``."""
    cls = torch.div(instance, INSTANCE_DIVISOR, rounding_mode="floor").clamp(0, position.numel() - 1)
    mask = (instance > 0) & (position[cls] >= 0) & valid
    seg, batch, ids = instance_segments(instance, mask)
    return seg, batch, position[torch.div(ids, INSTANCE_DIVISOR, rounding_mode="floor")]


def pq_stats(
    pred_instance: Tensor,
    gt_instance: Tensor,
    gt_label: Tensor,
    thing_classes: Sequence[int],
    ignore_index: int = IGNORE_INDEX,
) -> Tensor:
    """Panoptic-quality sums of one batch.

    Args:
        pred_instance: ``(B, H, W)`` predicted ids ``class_id * 1000 + k`` (0 = none).
        gt_instance: ``(B, H, W)`` ground-truth ids, same convention.
        gt_label: ``(B, H, W)`` ground-truth semantic map (``ignore_index`` = void).
        thing_classes: the ``T`` class ids evaluated.

    Returns:
        ``(4, T)`` float64: rows ``iou_sum, tp, fp, fn`` per thing class (in ``thing_classes`` order).
    """
    if pred_instance.shape != gt_instance.shape or gt_instance.shape != gt_label.shape or gt_label.dim() != 3:
        raise ValueError(f"pred_instance, gt_instance and gt_label must all be (B, H, W); got "
                         f"{tuple(pred_instance.shape)}, {tuple(gt_instance.shape)}, {tuple(gt_label.shape)}")
    device = gt_label.device
    things = torch.as_tensor(list(thing_classes), dtype=torch.long, device=device)
    t = things.numel()
    stats = torch.zeros(4, t, dtype=torch.float64, device=device)
    if t == 0:
        return stats
    max_class = max(int(things.max()),
                    int(torch.div(pred_instance.max(), INSTANCE_DIVISOR, rounding_mode="floor")),
                    int(torch.div(gt_instance.max(), INSTANCE_DIVISOR, rounding_mode="floor")))
    position = torch.full((max_class + 1,), -1, dtype=torch.long, device=device)
    position[things] = torch.arange(t, device=device)

    valid = gt_label != ignore_index
    gseg, _, gcls = _segments_of_things(gt_instance, position, valid)
    pseg_all, _, pcls = _segments_of_things(pred_instance, position, torch.ones_like(valid))
    ng, np_ = gcls.numel(), pcls.numel()
    pseg = torch.where(valid, pseg_all, torch.full_like(pseg_all, -1))
    garea = torch.bincount(gseg[gseg >= 0], minlength=ng)
    parea = torch.bincount(pseg[pseg >= 0], minlength=np_)  # non-void area
    pfull = torch.bincount(pseg_all[pseg_all >= 0], minlength=np_)

    both = (gseg >= 0) & (pseg >= 0)
    pair, inter = torch.unique(gseg[both] * max(np_, 1) + pseg[both], return_counts=True)
    pg, pp = torch.div(pair, max(np_, 1), rounding_mode="floor"), pair % max(np_, 1)
    iou = inter.double() / (garea[pg] + parea[pp] - inter).double()
    match = (iou > 0.5) & (gcls[pg] == pcls[pp])
    g_matched = torch.zeros(ng, dtype=torch.bool, device=device)
    p_matched = torch.zeros(np_, dtype=torch.bool, device=device)
    g_matched[pg[match]] = True
    p_matched[pp[match]] = True

    # Unmatched predictions lying mostly on void or on crowd pixels of their class are not counted.
    in_pred = pseg_all >= 0
    pred_cls_pix = things[pcls[pseg_all[in_pred]]]
    crowd = (gt_label[in_pred] == pred_cls_pix) & (gt_instance[in_pred] == 0)
    excluded = (~valid[in_pred]) | crowd
    pexcl = torch.bincount(pseg_all[in_pred][excluded], minlength=np_)
    fp = (~p_matched) & (pexcl.double() <= 0.5 * pfull.double())

    ones = torch.ones((), dtype=torch.float64, device=device)
    stats[0].index_add_(0, gcls[pg[match]], iou[match])
    stats[1].index_add_(0, gcls[pg[match]], ones.expand(int(match.sum())))
    stats[2].index_add_(0, pcls[fp], ones.expand(int(fp.sum())))
    stats[3].index_add_(0, gcls[~g_matched], ones.expand(int((~g_matched).sum())))
    return stats


def pq_from_stats(stats: Tensor) -> dict[str, Tensor]:
    """``{'pq', 'sq', 'rq'}`` per class ``(T,)`` from summed :func:`pq_stats` ``(4, T)``; NaN for a class
    with neither ground-truth nor predicted segments (leave it out of means: ``nanmean``)."""
    iou_sum, tp, fp, fn = stats.double()
    denom = tp + 0.5 * fp + 0.5 * fn
    nan = torch.full_like(denom, float("nan"))
    pq = torch.where(denom > 0, iou_sum / denom.clamp_min(1e-12), nan)
    sq = torch.where(tp > 0, iou_sum / tp.clamp_min(1e-12), torch.where(denom > 0, torch.zeros_like(nan), nan))
    rq = torch.where(denom > 0, tp / denom.clamp_min(1e-12), nan)
    return {"pq": pq, "sq": sq, "rq": rq}
