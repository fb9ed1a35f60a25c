"""Recall of object proposals: how many of a frame's annotated objects a proposal map finds.

3D-SDN edits the objects its semantic branch proposes; an object without a proposal cannot be moved,
deleted or recoloured, and its pixels are drawn as background. The paper evaluates objects of more than
256 visible pixels (at Virtual KITTI's 624x192 working size). A ground-truth object is **found** when some
proposal covers it with IoU >= 0.5 (``iou_threshold``); each proposal finds at most one object (greedy by
IoU, so ties at exactly 0.5 cannot count one proposal twice).

Two matchings are counted: *class-agnostic* (any thing proposal, what the editing path needs: it edits the
object whatever its class) and *class-aware* (the proposal's class is the object's). Precision is the share
of proposals that cover some annotated object (of any size) with IoU >= 0.5.

:func:`match_proposals` counts one frame; add the :class:`RecallCounts` of a part with ``+`` and read them
with :meth:`RecallCounts.summary`. :func:`predictor_recall` runs a semantic branch over frame records (the
demo's report and ``benchmarks/proposal_recall.py``).

    >>> import torch
    >>> gt = torch.zeros(1, 8, 8, dtype=torch.long); gt[0, :4, :4] = 13001; gt[0, 4:, 4:] = 13002
    >>> pred = torch.zeros(1, 8, 8, dtype=torch.long); pred[0, :4, :3] = 14001
    >>> counts = match_proposals(pred, gt, thing_classes=[13, 14], min_pixels=10)
    >>> counts.summary()["recall"], counts.summary()["recall_class_aware"]
    (0.5, 0.0)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import torch
from torch import Tensor

from sdn3d.data.frames import load_frame
from sdn3d.data.records import FrameRecord
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.predict import SemanticPredictor

__all__ = ["RecallCounts", "match_proposals", "predictor_recall", "PAPER_MIN_PIXELS", "PAPER_SIZE",
           "min_pixels_at"]

#: The paper's object filter: more than this many visible pixels at 624x192 (:data:`PAPER_SIZE`).
PAPER_MIN_PIXELS = 256
#: ``(W, H)`` of Virtual KITTI's working size, where :data:`PAPER_MIN_PIXELS` applies.
PAPER_SIZE = (624, 192)


def min_pixels_at(width: int, height: int) -> float:
    """The paper's filter at another image size: :data:`PAPER_MIN_PIXELS` scaled by the area.

    >>> min_pixels_at(312, 96)
    64.0
    """
    return PAPER_MIN_PIXELS * width * height / (PAPER_SIZE[0] * PAPER_SIZE[1])


@dataclass
class RecallCounts:
    """Counts over frames, per ground-truth thing class id.

    Attributes:
        objects: evaluated ground-truth objects (over ``min_pixels``) per class.
        found: those a proposal covers with IoU >= the threshold (class-agnostic).
        found_class_aware: those a proposal *of their class* covers.
        iou_sum: sum over found objects of their proposal's IoU.
        proposals: proposals (any size), and ``true_proposals``: those covering an annotated object.
        frames: frames counted.
    """

    objects: dict[int, int] = field(default_factory=dict)
    found: dict[int, int] = field(default_factory=dict)
    found_class_aware: dict[int, int] = field(default_factory=dict)
    iou_sum: float = 0.0
    proposals: int = 0
    true_proposals: int = 0
    frames: int = 0

    def __add__(self, other: RecallCounts) -> RecallCounts:
        def add(a: dict[int, int], b: dict[int, int]) -> dict[int, int]:
            return {k: a.get(k, 0) + b.get(k, 0) for k in sorted(set(a) | set(b))}

        return RecallCounts(add(self.objects, other.objects), add(self.found, other.found),
                            add(self.found_class_aware, other.found_class_aware), self.iou_sum + other.iou_sum,
                            self.proposals + other.proposals, self.true_proposals + other.true_proposals,
                            self.frames + other.frames)

    def summary(self, class_names: dict[int, str] | None = None) -> dict:
        """Recall (agnostic and class-aware), precision, mean IoU of found objects, and per class."""
        names = class_names or {}
        total, found = sum(self.objects.values()), sum(self.found.values())
        per_class = {names.get(c, str(c)): {"objects": n, "recall": _ratio(self.found.get(c, 0), n),
                                            "recall_class_aware": _ratio(self.found_class_aware.get(c, 0), n)}
                     for c, n in self.objects.items()}
        return {"frames": self.frames, "objects": total, "recall": _ratio(found, total),
                "recall_class_aware": _ratio(sum(self.found_class_aware.values()), total),
                "precision": _ratio(self.true_proposals, self.proposals), "proposals": self.proposals,
                "mean_iou_found": _ratio(self.iou_sum, found), "per_class": per_class}


def _ratio(a: float, b: float) -> float:
    return a / b if b else float("nan")


def _lookup(ids: Tensor, flat: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """``(index into ids, pixel is one of ids, area per id)`` for the pixels ``flat`` and sorted ``ids``."""
    if not len(ids):
        return torch.zeros_like(flat), torch.zeros_like(flat, dtype=torch.bool), torch.zeros(0, dtype=torch.long)
    index = torch.searchsorted(ids, flat).clamp(max=len(ids) - 1)
    member = ids[index] == flat
    return index, member, torch.bincount(index[member], minlength=len(ids))


def match_proposals(pred_instance: Tensor, gt_instance: Tensor, thing_classes: Sequence[int],
                    min_pixels: int = PAPER_MIN_PIXELS, iou_threshold: float = 0.5) -> RecallCounts:
    """Match the proposals of ``pred_instance`` to the objects of ``gt_instance``.

    Args:
        pred_instance: ``(B, H, W)`` int64 proposal ids ``class_id * 1000 + k`` (0 = none).
        gt_instance: ``(B, H, W)`` ground-truth instance ids, same convention and size.
        thing_classes: class ids whose instances count (proposals and objects of other classes are ignored).
        min_pixels: an object is evaluated when it has more visible pixels than this.
        iou_threshold: IoU at which a proposal finds an object.

    Returns:
        the frame's :class:`RecallCounts` (``frames = B``).
    """
    if pred_instance.shape != gt_instance.shape or gt_instance.dim() != 3:
        raise ValueError(f"pred_instance and gt_instance must both be (B, H, W); got {tuple(pred_instance.shape)} "
                         f"and {tuple(gt_instance.shape)}")
    things = torch.as_tensor(list(thing_classes), dtype=torch.long)
    counts = RecallCounts(frames=int(gt_instance.shape[0]))
    for pred, gt in zip(pred_instance.cpu().long(), gt_instance.cpu().long(), strict=True):  # a (P, G) table per frame
        pred_flat, gt_flat = pred.flatten(), gt.flatten()
        p_ids, g_ids = pred_flat.unique(), gt_flat.unique()
        p_ids = p_ids[(p_ids >= INSTANCE_DIVISOR) & torch.isin(p_ids // INSTANCE_DIVISOR, things)]
        g_ids = g_ids[(g_ids >= INSTANCE_DIVISOR) & torch.isin(g_ids // INSTANCE_DIVISOR, things)]
        p_index, p_member, p_area = _lookup(p_ids, pred_flat)
        g_index, g_member, g_area = _lookup(g_ids, gt_flat)
        # (P, G) intersections from the joint (proposal, object) index of every pixel.
        both = p_member & g_member
        inter = torch.zeros(len(p_ids) * len(g_ids), dtype=torch.long)
        inter.index_add_(0, (p_index * len(g_ids) + g_index)[both], torch.ones(int(both.sum()), dtype=torch.long))
        inter = inter.view(len(p_ids), len(g_ids)).double()
        iou = inter / (p_area[:, None] + g_area[None] - inter).clamp(min=1)
        # Greedy one-to-one assignment, highest IoU first.
        agnostic = _assign(iou, iou_threshold)
        aware = _assign(torch.where((p_ids // INSTANCE_DIVISOR)[:, None] == (g_ids // INSTANCE_DIVISOR)[None], iou,
                                    torch.zeros_like(iou)), iou_threshold)
        evaluated = g_area > min_pixels
        g_cls = (g_ids // INSTANCE_DIVISOR).tolist()
        for j, c in enumerate(g_cls):
            if not bool(evaluated[j]):
                continue
            counts.objects[c] = counts.objects.get(c, 0) + 1
            if agnostic[j] >= 0:
                counts.found[c] = counts.found.get(c, 0) + 1
                counts.iou_sum += float(iou[agnostic[j], j])
            if aware[j] >= 0:
                counts.found_class_aware[c] = counts.found_class_aware.get(c, 0) + 1
        counts.proposals += len(p_ids)
        counts.true_proposals += int((agnostic >= 0).sum())
    counts.objects = dict(sorted(counts.objects.items()))
    return counts


def _assign(iou: Tensor, threshold: float) -> Tensor:
    """``(G,)`` index of the proposal assigned to each object (-1: none), greedy by IoU over ``iou (P, G)``."""
    assigned = torch.full((iou.shape[1],), -1, dtype=torch.long)
    if iou.numel() == 0:
        return assigned
    order = torch.argsort(iou.flatten(), descending=True)
    used_p: set[int] = set()
    for flat in order.tolist():
        p, g = divmod(flat, iou.shape[1])
        if float(iou[p, g]) < threshold:
            break
        if p in used_p or assigned[g] >= 0:
            continue
        used_p.add(p)
        assigned[g] = p
    return assigned


@torch.no_grad()
def predictor_recall(records: Sequence[FrameRecord], predictor: SemanticPredictor,
                     min_pixels: int = PAPER_MIN_PIXELS, references: Callable[[Tensor, Tensor], dict] | None = None,
                     ) -> tuple[RecallCounts, dict[str, RecallCounts]]:
    """The recall of ``predictor``'s instance proposals over ``records``, each read at its own size.

    The predictor runs at its ``image_size`` if it has one (its maps come back to the frame's size, nearest).
    ``references(label (H, W), gt_semantic (H, W)) -> {name: proposal map (H, W)}``, optional: other proposal
    maps counted on the same objects (e.g. connected components, for a floor and a ceiling).

    Returns:
        ``(counts of the instance head, {name: counts of each reference})``.
    """
    things = list(predictor.thing_classes)
    counts, refs = RecallCounts(), {}
    for record in records:
        frame = load_frame(record, None)
        seg = predictor(frame.image)
        gt = frame.instances[None]
        counts += match_proposals(seg.instance.cpu(), gt, things, min_pixels)
        for name, proposal_map in (references(seg.label[0].cpu(), frame.semantic) if references else {}).items():
            refs[name] = refs.get(name, RecallCounts()) + match_proposals(proposal_map[None], gt, things, min_pixels)
    return counts, refs
