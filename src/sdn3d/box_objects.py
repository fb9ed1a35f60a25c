"""Objects a person named by a box (:class:`BoxPrompts`, an edit spec's ``objects:``): the box sub-pipeline of
:func:`sdn3d.derender.derender`, and the typed record of each one's fit (:class:`BoxFit`, ``scene.meta['boxes']``).

1. :func:`add_box_objects`: GrabCut masks in the boxes (:mod:`sdn3d.box_masks`, nearest first; or the masks given),
   each taking its pixels from the other proposals (a proposal left with less than half its pixels is dropped).
2. :func:`fit_box_objects`: the geometric branch's prediction (when there is one) only starts
   :func:`~sdn3d.geometric.fit.fit_to_masks`: every template and four yaws fitted to each box object's mask on the road
   plane, other objects' pixels ignored; where the fit matched, the mask is segmented again seeded by the fitted
   shape (:func:`~sdn3d.box_masks.refine_with_silhouettes`). Its result per box is a :class:`BoxFit` (mask source,
   pose source, silhouette IoU, poor flag); :meth:`BoxFit.to_json` is the form scene files and reports show.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import TYPE_CHECKING, Any

import torch
from torch import Tensor

from sdn3d.errors import UserInputError
from sdn3d.labels import INSTANCE_DIVISOR, SemanticClass
from sdn3d.math3d.camera import Intrinsics
from sdn3d.meshes.bank import default_bank
from sdn3d.road_heading import road_axes

if TYPE_CHECKING:
    from sdn3d.box_masks import BoxMasks
    from sdn3d.geometric.facing import Appearance
    from sdn3d.geometric.fit import FitRequest, FitResult, FitSettings
    from sdn3d.semantic.predict import Segmentation

__all__ = ["BoxFit", "BoxPrompts", "MaskSource", "PoseSource", "add_box_objects", "box_grabcut", "box_fits",
           "box_request", "fit_box_objects", "fitted_silhouettes", "occluder_masks"]


class MaskSource(Enum):
    """Where a box object's mask came from."""

    GIVEN = "given"  #: BoxPrompts.masks (e.g. drawn by a person)
    GRABCUT = "grabcut"
    GRABCUT_PRIOR = "grabcut_prior"  #: GrabCut seeded by the semantic branch's object probability
    WHOLE_BOX = "whole_box"  #: the box itself, where GrabCut found too little in it


class PoseSource(Enum):
    """Where a box object's 3D fit started (the fit itself is always to the mask)."""

    PREDICTION = "prediction"  #: the geometric branch's prediction
    ROAD_PLANE = "road_plane"  #: the box on the road plane (no prediction)


# How scene files and reports say them (BoxFit.to_json; read back by BoxFit.from_json).
_MASK_TEXT = {MaskSource.GIVEN: "given", MaskSource.GRABCUT: "grabcut",
              MaskSource.GRABCUT_PRIOR: "grabcut, seeded by the semantic branch",
              MaskSource.WHOLE_BOX: "the whole box (GrabCut found too little in it)"}
_REFINED_TEXT = ", then again seeded by its fitted 3D shape"
_POSE_TEXT = {PoseSource.PREDICTION: "fitted to the mask from the geometric branch's prediction",
              PoseSource.ROAD_PLANE: "fitted to the mask from the box on the road plane"}


@dataclass(frozen=True)
class BoxFit:
    """One box object's fit (``scene.meta['boxes']``, in the boxes' order).

    Attributes:
        instance_id: the object's instance id.
        box: its box ``(x0, y0, x1, y1)`` in the working image's pixels.
        mask_source: where its mask came from; ``mask_refined``: segmented again, seeded by its fitted 3D shape.
        mask_pixels: its mask's pixels (the final mask).
        pose_source: where its 3D fit started; None: no fit (``fit_pixels < min_pixels``).
        iou: the fit's silhouette IoU with its mask (None: no fit).
        poor: no fit, or ``iou`` under the fit settings' ``poor_iou``.
        fit_pixels, min_pixels: its mask's pixels before the fit, and the pixels a fit needs (what a record without
            a fit says; read back from a scene file, ``fit_pixels`` of a fitted one is ``mask_pixels``).
        hypothesis: which of the fit's hypotheses won, in words (:meth:`~sdn3d.geometric.fit.FitResult.hypothesis_name`:
            the prediction, its end-for-end flip, its mirror about the line of sight, the mirror's flip, a search
            start; None: no fit).
        fit_note: what the fit could not do normally (a mask too small or thin: the prediction kept), or None.
        road_axis_deg: the road's axis its fit was drawn towards (a yaw in degrees, either end;
            :func:`~sdn3d.road_heading.road_axes`, weighed by the fit settings' ``lane_reg``); None: none (no fit, a
            ``lane_reg`` of 0, or the edges around it did not tell).
    """

    instance_id: int
    box: tuple[float, float, float, float]
    mask_source: MaskSource
    mask_refined: bool
    mask_pixels: int
    pose_source: PoseSource | None
    iou: float | None
    poor: bool
    fit_pixels: int
    min_pixels: int
    hypothesis: str | None = None
    fit_note: str | None = None
    road_axis_deg: float | None = None

    def to_json(self) -> dict[str, Any]:
        """The record as scene files and reports write it (``box``, ``mask_pixels``, ``pose``, ``fit_iou``,
        ``poor_fit``, ``why`` where there is no fit, ``id``, ``mask``; ``hypothesis``, ``fit_note`` and
        ``road_axis_deg`` where there are)."""
        out: dict[str, Any] = {"box": [round(float(v), 2) for v in self.box], "mask_pixels": self.mask_pixels,
                               "pose": None if self.pose_source is None else _POSE_TEXT[self.pose_source],
                               "fit_iou": None if self.iou is None else round(self.iou, 4), "poor_fit": self.poor}
        if self.iou is None:
            out["why"] = f"its mask has {self.fit_pixels} pixels (< min_pixels {self.min_pixels}): no 3D fit"
        out["id"] = self.instance_id
        out["mask"] = _MASK_TEXT[self.mask_source] + (_REFINED_TEXT if self.mask_refined else "")
        if self.hypothesis is not None:
            out["hypothesis"] = self.hypothesis
        if self.fit_note is not None:
            out["fit_note"] = self.fit_note
        if self.road_axis_deg is not None:
            out["road_axis_deg"] = round(self.road_axis_deg, 2)
        return out

    @classmethod
    def from_json(cls, record: Mapping[str, Any], min_pixels: int | None = None) -> BoxFit:
        """The record :meth:`to_json` wrote (e.g. read back from a scene file; ``min_pixels``: the scene's
        ``meta['min_pixels']``, the pixels a fit needed where the record has no fit)."""
        mask = str(record["mask"])
        refined = mask.endswith(_REFINED_TEXT)
        mask = mask[: -len(_REFINED_TEXT)] if refined else mask
        poses = {v: k for k, v in _POSE_TEXT.items()}
        iou = record.get("fit_iou")
        fit_pixels = int(record["mask_pixels"])
        if iou is None and "why" in record:  # "its mask has N pixels (< min_pixels M): no 3D fit"
            words = str(record["why"]).split()
            fit_pixels, min_pixels = int(words[3]), int(words[6].rstrip("):"))
        return cls(int(record["id"]), tuple(float(v) for v in record["box"]),
                   {v: k for k, v in _MASK_TEXT.items()}[mask], refined, int(record["mask_pixels"]),
                   None if record.get("pose") is None else poses[record["pose"]],
                   None if iou is None else float(iou), bool(record["poor_fit"]), fit_pixels,
                   int(min_pixels) if min_pixels is not None else 0, record.get("hypothesis"), record.get("fit_note"),
                   None if record.get("road_axis_deg") is None else float(record["road_axis_deg"]))


def box_fits(meta: Mapping[str, Any]) -> list[BoxFit]:
    """A scene's ``meta['boxes']`` as :class:`BoxFit` records (records read back from a scene file are parsed)."""
    return [r if isinstance(r, BoxFit) else BoxFit.from_json(r, meta.get("min_pixels"))
            for r in meta.get("boxes", [])]


@dataclass(frozen=True)
class BoxPrompts:
    """Objects a person named by a box (real photos need nothing else; :mod:`sdn3d.derender`'s step 2).

    Attributes:
        boxes: ``(N, 4)`` float half-open ``(x0, y0, x1, y1)`` in the working image's pixels.
        classes: the class of each, a name (case ignored) or an id of an instance class of the scene's class list.
        fit: the 3D fit (:class:`~sdn3d.geometric.fit.FitSettings`; None: its defaults, set on creation).
        prior: seed GrabCut with the semantic branch's vehicle probability (only when that branch is trusted).
        iterations: GrabCut iterations per box.
        masks: ``(N, H, W)`` bool visible masks to take instead of GrabCut's (e.g. drawn by a person), or None.
        refine_masks: segment each GrabCut mask again, seeded by the object's fitted 3D shape
            (:func:`~sdn3d.box_masks.refine_with_silhouettes`), where the fit matched its mask (not a poor fit).

    The ``i``-th box becomes instance ``class_id * 1000 + k`` with ``k`` the next free number of its class, in the
    boxes' order.
    """

    boxes: Tensor
    classes: tuple[str | int, ...]
    fit: FitSettings | None = None
    prior: bool = False
    iterations: int = 5
    masks: Tensor | None = None
    refine_masks: bool = True

    def __post_init__(self) -> None:
        boxes, classes = torch.as_tensor(self.boxes, dtype=torch.float32), tuple(self.classes)
        if boxes.dim() != 2 or boxes.shape[1] != 4 or len(classes) != boxes.shape[0]:
            raise ValueError(f"BoxPrompts: boxes must be (N, 4) with one class each, got {tuple(boxes.shape)} and "
                             f"{len(classes)} classes")
        if not bool(torch.isfinite(boxes).all()) or bool(((boxes[:, 2:] - boxes[:, :2]) < 1).any()):
            raise ValueError("BoxPrompts: every box needs finite x0 < x1 and y0 < y1")
        object.__setattr__(self, "boxes", boxes)
        object.__setattr__(self, "classes", classes)
        if self.fit is None:
            from sdn3d.geometric.fit import FitSettings

            object.__setattr__(self, "fit", FitSettings())
        if self.masks is not None and (self.masks.dim() != 3 or self.masks.shape[0] != boxes.shape[0]):
            raise ValueError(f"BoxPrompts: masks must be (N, H, W) with N = {boxes.shape[0]}, got "
                             f"{tuple(self.masks.shape)}")

    def class_ids(self, class_list: Sequence[SemanticClass]) -> list[int]:
        """The boxes' class ids in ``class_list``.

        Raises:
            UserInputError: naming the box, for a class that is not an instance class of the list.
        """
        things = {c.name.lower(): c.id for c in class_list if c.has_instances}
        out = []
        for i, cls in enumerate(self.classes):
            cid = things.get(cls.lower()) if isinstance(cls, str) else (int(cls) if int(cls) in things.values()
                                                                        else None)
            if cid is None:
                raise UserInputError(f"box object {i}: class {cls!r} is not an object class; give one of "
                                     f"{sorted(c.name for c in class_list if c.has_instances)}")
            out.append(cid)
        return out

    def __len__(self) -> int:
        return int(self.boxes.shape[0])


def add_box_objects(image: Tensor, masks: Tensor, ids: Tensor, boxes: BoxPrompts, seg: Segmentation | None,
                    things: Tensor, class_list: Sequence[SemanticClass], found: BoxMasks | None = None
                    ) -> tuple[Tensor, Tensor, Tensor, list[MaskSource]]:
    """``(masks, ids, box_rows, each box's mask source)``: the proposals with the box objects' GrabCut masks appended
    (they take their pixels from the other proposals; a proposal left with less than half its pixels is dropped).
    ``found``: :func:`box_grabcut`'s masks, found already (while the semantic branch ran); used where GrabCut takes no
    prior (``boxes.prior`` off, or no ``seg``), else GrabCut runs here."""
    from sdn3d.box_masks import grabcut_masks, nearest_first

    class_ids = boxes.class_ids(class_list)
    prior = None
    if boxes.prior and seg is not None:  # the branch's probability of any object class
        probability = seg.probability[0].cpu()
        prior = probability[things[things < probability.shape[0]]].sum(0)
    if boxes.masks is not None:
        if tuple(boxes.masks.shape[-2:]) != tuple(image.shape[-2:]):
            raise ValueError(f"BoxPrompts.masks are {tuple(boxes.masks.shape[-2:])}, the image is "
                             f"{tuple(image.shape[-2:])}")
        order = nearest_first(boxes.boxes)  # one owner per pixel: the nearest, as GrabCut's masks have
        given = boxes.masks.bool().cpu()[order]
        box_masks = torch.empty_like(given)
        box_masks[order] = given & ~(torch.cumsum(given.long(), 0) - given.long()).bool()
        source = [MaskSource.GIVEN] * len(boxes)
    else:
        box_masks, from_box = (found if found is not None and prior is None
                               else grabcut_masks(image, boxes.boxes, prior=prior, iterations=boxes.iterations))
        grabcut = MaskSource.GRABCUT_PRIOR if prior is not None else MaskSource.GRABCUT
        source = [MaskSource.WHOLE_BOX if f else grabcut for f in from_box.tolist()]
    taken = box_masks.any(0)
    before = masks.flatten(1).sum(1)
    masks = masks & ~taken
    kept = masks.flatten(1).sum(1) * 2 >= before.clamp_min(1)
    masks, ids = masks[kept], ids[kept]
    new_ids = []
    for cid in class_ids:  # the next free number of each class, in the boxes' order
        used = [int(i) for i in ids.tolist() + new_ids if int(i) // INSTANCE_DIVISOR == cid]
        new_ids.append(cid * INSTANCE_DIVISOR + (max(used) % INSTANCE_DIVISOR if used else 0) + 1)
    rows = torch.arange(len(ids), len(ids) + len(boxes))
    return (torch.cat([masks, box_masks]), torch.cat([ids, torch.tensor(new_ids, dtype=ids.dtype)]), rows, source)


def box_grabcut(image: Tensor, boxes: BoxPrompts | None) -> BoxMasks | None:
    """The box objects' GrabCut masks where they need no semantics (no given masks, ``boxes.prior`` off): what
    :func:`add_box_objects` would find, for a caller that runs it beside the semantic branch; else None."""
    from sdn3d.box_masks import grabcut_masks

    if boxes is None or not len(boxes) or boxes.masks is not None or boxes.prior:
        return None
    return grabcut_masks(image, boxes.boxes, iterations=boxes.iterations)


def fit_box_objects(image: Tensor, intr: Intrinsics, masks: Tensor, ids: Tensor, rows: Tensor, boxes: BoxPrompts,
                    geometry: tuple[Tensor, ...], min_pixels: int, mask_source: Sequence[MaskSource],
                    appearance: Appearance | None = None, fit_result: FitResult | None = None,
                    classes: Sequence[str | None] | None = None, axes: Tensor | None = None
                    ) -> tuple[Tensor, tuple[Tensor, ...], list[BoxFit], Tensor | None]:
    """``(masks, geometry, each box's BoxFit, vacated)``: the box objects' rows ``rows`` fitted to their masks
    (:func:`~sdn3d.geometric.fit.fit_to_masks`, the geometric branch's prediction as the start) and, unless the masks
    were given or ``boxes.refine_masks`` is off, their masks segmented again seeded by the fits that matched;
    ``vacated``: the pixels of the first masks (what the second ones leave of them is no object's), else None.
    ``appearance``: what the geometric branch saw of each row of ``masks`` (lamps, its yaw before them, its bins):
    with ``boxes.fit.appearance`` the fit's yaw belief at each hypothesis' axis
    (:func:`~sdn3d.geometric.facing.facing_belief`); else the yaw nearest the prediction's is believed.
    ``fit_result``: the fit of :func:`box_request`'s objects, done by the caller together with others
    (:func:`~sdn3d.geometric.fit.fit_many`); None: fitted here. ``classes``: the class name of every row of
    ``masks`` (the templates each box object may be drawn with, :func:`~sdn3d.geometric.fit.allowed_templates`).
    Fitted here, each is drawn towards the road's axis where it stands (:func:`~sdn3d.road_heading.road_axes`,
    every object's pixels left out of the vote) with ``boxes.fit.lane_reg``; a caller's ``fit_result`` was asked for
    with ``axes``, ``(B,)`` the road's axis at each box object (NaN: unknown; None: none). Each record names its
    axis (:attr:`BoxFit.road_axis_deg`)."""
    if fit_result is None:  # the lane prior (fit module doc)
        axes = road_axes(image, intr.matrix(), masks[rows], masks.any(0)) if boxes.fit.lane_reg and len(rows) else None
    geometry, fitted = _fit_boxes(intr, masks, rows, boxes, geometry, min_pixels, appearance, fit_result, classes,
                                  axes)
    pixels = masks[rows].flatten(1).sum(1)
    final = [int(p) for p in pixels]
    again, vacated = [False] * len(boxes), None
    if boxes.masks is None and boxes.refine_masks:
        vacated = masks[rows].any(0)
        good = [iou is not None and not poor for _, iou, poor, *_ in fitted]
        masks, again, refined = _refine_box_masks(image, intr, masks, rows, boxes, geometry, good)
        if refined is not None:
            final = [int(m.sum()) for m in refined]
    axis = [None] * len(boxes)
    if axes is not None and boxes.fit.lane_reg:
        axis = [None if iou is None or not math.isfinite(v) else math.degrees(v)
                for v, (_, iou, *_) in zip(axes.tolist(), fitted, strict=True)]
    fits = [BoxFit(int(iid), tuple(float(v) for v in boxes.boxes[i]), source, a, final[i], pose, iou, poor,
                   int(pixels[i]), min_pixels, hypothesis, note, axis[i])
            for i, (iid, source, a, (pose, iou, poor, hypothesis, note)) in enumerate(
                zip(ids[rows].tolist(), mask_source, again, fitted, strict=True))]
    return masks, geometry, fits, vacated


def yaw_belief(appearance: Appearance | None, rows: Tensor) -> Callable[[Tensor], Tensor] | None:
    """The fit's yaw belief of the objects ``rows``: the appearance's (:func:`~sdn3d.geometric.facing.facing_belief`)
    where the branch predicted them, else facing away from the camera (the fit's first start without a prediction,
    ``ry = -pi/2``); None without an appearance (the fit's own default: the yaw nearest its start)."""
    if appearance is None:
        return None
    seen = appearance.rows(rows)
    if not bool(seen.has.any()):
        return None
    belief = seen.belief()

    def believed(ry: Tensor) -> Tensor:
        away = torch.cos(ry + math.pi / 2)
        return torch.where(seen.has[:, None], belief(ry).to(away.dtype), away)

    return believed


def box_request(masks: Tensor, rows: Tensor, boxes: BoxPrompts, geometry: tuple[Tensor, ...], min_pixels: int,
                appearance: Appearance | None = None, classes: Sequence[str | None] | None = None,
                axes: Tensor | None = None) -> FitRequest | None:
    """What :func:`fit_box_objects` asks the fit for (:class:`~sdn3d.geometric.fit.FitRequest`): the box objects'
    rows ``rows`` with at least ``min_pixels`` mask pixels (in the boxes' order; None: no box has them), each with
    the pixels that may hide it (every other proposal, and the boxes nearer than it: the farther ones it hides),
    the branch's prediction, where there is one, as its start, and its class (``classes``: the class name of every
    row of ``masks``; None: unknown), which bounds its templates. ``axes``: ``(B,)`` the road's axis at each box
    object, in the boxes' order (:func:`~sdn3d.road_heading.road_axes`, NaN: unknown), whose lane prior the fit adds
    with ``boxes.fit.lane_reg``; None: none."""
    from sdn3d.box_masks import nearest_first
    from sdn3d.geometric.fit import FitRequest

    template, dims, ry, location, _ = geometry
    sel = (masks[rows].flatten(1).sum(1) >= min_pixels).nonzero().flatten()
    if not len(sel):
        return None
    predicted = template[rows] >= 0
    order = nearest_first(boxes.boxes)
    rank = torch.empty_like(order)
    rank[order] = torch.arange(len(order))
    others = torch.ones(len(masks), dtype=torch.bool)
    others[rows] = False
    rest = masks[others].any(0) if bool(others.any()) else torch.zeros_like(masks[0])
    ignore = occluder_masks(masks[rows], rank.float()) | rest
    nan = torch.tensor(float("nan"))
    return FitRequest(masks[rows[sel]], boxes.boxes[sel], ignore=ignore[sel],
                      start_ry=torch.where(predicted[sel], ry[rows[sel]].float(), nan),
                      start_dims=torch.where(predicted[sel, None], dims[rows[sel]].float(), nan),
                      start_template=template[rows[sel]],
                      start_location=torch.where(predicted[sel, None], location[rows[sel]].float(), nan),
                      yaw_belief=yaw_belief(appearance if boxes.fit.appearance else None, rows[sel]),
                      classes=None if classes is None else [classes[int(r)] for r in rows[sel]],
                      road_ry=None if axes is None else axes[sel].float())


def _fit_boxes(intr: Intrinsics, masks: Tensor, rows: Tensor, boxes: BoxPrompts, geometry: tuple[Tensor, ...],
               min_pixels: int, appearance: Appearance | None = None, result: FitResult | None = None,
               classes: Sequence[str | None] | None = None, axes: Tensor | None = None
               ) -> tuple[tuple[Tensor, ...], list[tuple[PoseSource | None, float | None, bool, str | None,
                                                          str | None]]]:
    """The geometry with the box objects' rows fitted to their masks (:func:`~sdn3d.geometric.fit.fit_to_masks`,
    the geometric branch's prediction as the start) and per box ``(pose source, silhouette IoU, poor, winning
    hypothesis, the fit's note)`` (None, None, True, None, None: too few pixels, no fit). ``result``: the fit of
    :func:`box_request` done by the caller (with other objects'), else None: fitted here (``axes``: as
    :func:`box_request`'s)."""
    from sdn3d.geometric.fit import fit_many

    template, dims, ry, location, phi = (g.clone() for g in geometry)
    settings = boxes.fit
    fitted = masks[rows].flatten(1).sum(1) >= min_pixels
    predicted = template[rows] >= 0
    sel = fitted.nonzero().flatten()
    if result is None and len(sel):
        result = fit_many([box_request(masks, rows, boxes, geometry, min_pixels, appearance, classes, axes)], intr,
                          settings=settings)[0]
    if len(sel):
        target = rows[sel]
        template[target] = result.template
        dims[target], ry[target] = result.dims.double(), result.ry.double()
        location[target], phi[target] = result.location.double(), result.phi.float()
    else:
        result = None
    out, iou = [], dict(zip(sel.tolist(), result.iou.tolist(), strict=True)) if result is not None else {}
    at = {i: k for k, i in enumerate(sel.tolist())}  # box -> its row in the fit
    notes = result.notes if result is not None else {}
    for i in range(len(boxes)):
        fit_iou = iou.get(i)
        if fit_iou is None:
            template[rows[i]] = -1
            out.append((None, None, True, None, None))
        else:
            pose = PoseSource.PREDICTION if bool(predicted[i]) else PoseSource.ROAD_PLANE
            out.append((pose, fit_iou, fit_iou < settings.poor_iou, result.hypothesis_name(at[i]),
                        notes.get(at[i])))
    return (template, dims, ry, location, phi), out


def _refine_box_masks(image: Tensor, intr: Intrinsics, masks: Tensor, rows: Tensor, boxes: BoxPrompts,
                      geometry: tuple[Tensor, ...], good: list[bool]) -> tuple[Tensor, list[bool], Tensor | None]:
    """``(masks, each box's mask segmented again?, the box objects' new masks or None)``: the box objects' GrabCut
    masks segmented again, seeded by their fitted 3D shapes drawn in the image
    (:func:`~sdn3d.box_masks.refine_with_silhouettes`), for the boxes ``good`` (whose fit matched its mask)."""
    from sdn3d.box_masks import refine_with_silhouettes

    good = torch.tensor(good, dtype=torch.bool)
    if not bool(good.any()):
        return masks, [False] * len(good), None
    drawn = torch.zeros(len(good), *masks.shape[-2:], dtype=torch.bool)
    drawn[good] = fitted_silhouettes(intr, geometry, rows[good])
    others = torch.ones(len(masks), dtype=torch.bool)
    others[rows] = False
    again = refine_with_silhouettes(image, boxes.boxes, masks[rows], drawn, refine=good,
                                    others=masks[others].any(0) if bool(others.any()) else None,
                                    iterations=boxes.iterations)
    masks = masks.clone()
    masks[rows] = again
    return masks, good.tolist(), again


def fitted_silhouettes(intr: Intrinsics, geometry: tuple[Tensor, ...], rows: Tensor) -> Tensor:
    """``(K, H, W)`` bool: the hard silhouette (every face, the z-buffer's coverage) of each of the objects ``rows
    (K,)`` of ``geometry`` (``template (N,), dims (N, 3), ry (N,), location (N, 3), phi (N, 64, 3)``; templates of
    the default bank), each drawn alone in the image of ``intr``."""
    from sdn3d.math3d.transforms import bottom_to_center
    from sdn3d.render import RasterSettings, rasterize_meshes
    from sdn3d.render.objects import pose_meshes

    if not len(rows):
        return torch.zeros(0, intr.height, intr.width, dtype=torch.bool)
    template, dims, ry, location, phi = (g[rows] for g in geometry)
    center = bottom_to_center(location, dims[:, 1])
    verts, faces = pose_meshes(default_bank(), template.long(), dims.float(), ry.float(), center.float(), phi.float())
    # Drawn in the window the shapes cover (the same pixels as the whole image's): whole-image maps of every kind, for
    # one boolean each, cost a tenth of a second of page faults for ten box objects at 624x192 (issue 40).
    fragments = rasterize_meshes(verts, faces, intr.matrix().float(), RasterSettings((intr.height, intr.width)),
                                 crop=True)
    return fragments.in_image(fragments.mask, False)


def occluder_masks(masks: Tensor, depth: Tensor) -> Tensor:
    """``(N, H, W)`` bool: for each object, the pixels of the ``masks (N, H, W)`` of the objects nearer than it
    (``depth (N,)``, e.g. predicted box-centre z), which its silhouette may cover unseen.

    >>> masks = torch.zeros(2, 1, 4, dtype=torch.bool); masks[0, 0, :2] = True; masks[1, 0, 1:] = True
    >>> occluder_masks(masks, torch.tensor([5.0, 9.0]))[:, 0].int().tolist()  # object 0 is in front
    [[0, 0, 0, 0], [1, 1, 0, 0]]
    """
    nearer = (depth[None, :] < depth[:, None]).float()  # (N, N): row i, column j in front of i
    return (nearer @ masks.flatten(1).float()).view(masks.shape) > 0
