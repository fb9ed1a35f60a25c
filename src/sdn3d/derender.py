"""De-render an image into a :class:`~sdn3d.scene.code.SceneCode`, and render scenes back (3D-SDN, Fig. 2).

:func:`derender` runs the three branches on one image:

1. **Semantics**: the semantic branch's label map (or the frame's ground truth with
   ``proposals='gt'``, or when there is no semantic model). Object pixels are labelled with their
   object's class, so the map is the background the objects are drawn on (:mod:`sdn3d.scene.code`).
2. **Proposals**: instance masks from the frame's ground-truth instance map when a
   :class:`GroundTruth` with one is given (``'auto'``, ``'gt'``: an oracle), else from the semantic
   branch's instance head (``'semantic'``); and objects a person named by a box (:class:`BoxPrompts`, with any of
   those or alone as ``'boxes'``): GrabCut masks (:mod:`sdn3d.box_masks`), nearest first, each taking its pixels
   from any other proposal; a proposal left with less than half its pixels is dropped.
3. **Geometry**: every object with at least ``min_pixels`` visible pixels becomes a square masked
   crop (the :class:`~sdn3d.data.datasets.GeometricDataset` recipe: its 2D box grown by ``margin``,
   resampled to ``crop_size``), all crops go through the geometric branch in one forward
   (:meth:`GeometricPredictor.predict`): template, FFD ``phi``, dims, yaw, location. The 2D box is
   the annotation's when the object comes from a ground-truth frame (what the branch is trained
   on), else the mask's bounding box. Objects without a prediction (no geometric model, too small,
   a box one pixel wide or high, non-finite output or behind the camera) keep only their 2D mask.
   A box object's prediction (when there is a geometric branch) only starts :func:`~sdn3d.geometric.fit.fit_to_masks`:
   every template and four yaws fitted to its mask on the road plane, other objects' pixels ignored; the scene's
   ``meta['boxes']`` records per box where its mask and pose came from and the fit's silhouette IoU.
4. **Texture**: the textural encoder pools one code per region of the instance label map ``L``
   (objects and background classes): :func:`encode_scene`.

Every object is *observed* and keeps its visible mask, so rendering an unedited scene redraws the
image's own layout; edits (:func:`sdn3d.editing.apply.apply_edits`) free the masks of moved objects.
Drawing a scene and editing an image end to end are :mod:`sdn3d.editing.render`.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import torch
from torch import Tensor

from sdn3d.errors import UserInputError
from sdn3d.image_ops import (
    crop_intrinsics,
    crop_windows,
    mask_boxes,
    pixel_centre_boxes,
    square_crop_window,
)
from sdn3d.labels import CLASS_LISTS, INSTANCE_DIVISOR, SemanticClass
from sdn3d.math3d.camera import Intrinsics
from sdn3d.meshes.bank import MeshBank, default_bank
from sdn3d.models import Models
from sdn3d.scene.code import DEFAULT_CODE_DIM, ObjectTable, SceneCode
from sdn3d.scene.maps import scene_maps

if TYPE_CHECKING:
    from sdn3d.geometric.fit import FitSettings
    from sdn3d.geometric.refine import RefineSettings
    from sdn3d.semantic.predict import Segmentation
    from sdn3d.textural.renderer import TexturalRenderer

__all__ = [
    "PROPOSALS",
    "PROPOSAL_LABELS",
    "BoxPrompts",
    "GroundTruth",
    "derender",
    "encode_scene",
    "occluder_masks",
]

log = logging.getLogger(__name__)

PROPOSALS = ("auto", "gt", "semantic", "boxes")
#: What a scene's objects and semantics came from, as every report says it (the oracle labelled).
PROPOSAL_LABELS = {"semantic": "predicted: the semantic branch's masks and semantics",
                   "gt": "oracle: ground-truth masks and semantics",
                   "boxes": "boxes given by the user: GrabCut masks, 3D fitted to them"}


@dataclass(frozen=True)
class GroundTruth:
    """A frame's ground truth at the working size, for oracle de-rendering (never needed for real images).

    Attributes:
        key: the frame's name (recorded in the scene's ``meta['source']``).
        classes: its class list name (``'vkitti'`` or ``'cityscapes'``).
        semantic: ``(H, W)`` int64 class indices.
        instances: ``(H, W)`` int64 instance ids (``class_id * 1000 + k``), or None.
        boxes: annotated 2D boxes by instance number ``k`` (``id % 1000``): ``(4,)`` float pixel-centre
            ``(l, t, r, b)`` at the working size (the geometric branch's training boxes).
    """

    key: str
    classes: str
    semantic: Tensor
    instances: Tensor | None = None
    boxes: Mapping[int, Tensor] = field(default_factory=dict)


@dataclass(frozen=True)
class BoxPrompts:
    """Objects a person named by a box (step 2 of the module doc; real photos need nothing else).

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


# -- de-rendering -----------------------------------------------------------------------------


def _class_list_name(models: Models, gt: GroundTruth | None, classes: str | None) -> str:
    if classes is not None:
        if classes not in CLASS_LISTS:
            raise ValueError(f"classes must be one of {sorted(CLASS_LISTS)}, got {classes!r}")
        return classes
    if gt is not None:
        return gt.classes
    count = (len(models.semantic.classes) if models.semantic is not None
             else models.textural.spec.num_classes if models.textural is not None else None)
    names = [k for k, v in CLASS_LISTS.items() if len(v) == count]
    if not names:
        raise UserInputError(f"cannot tell the class list from the models ({count} classes): pass classes=")
    return names[0]


def _predict_geometry(image: Tensor, intr: Intrinsics, masks: Tensor, boxes: Tensor, models: Models,
                      refine: RefineSettings | None) -> dict[str, Tensor]:
    """Batched geometric branch on the objects ``masks (N, H, W)`` with 2D ``boxes (N, 4)``.

    With ``refine`` (the paper's Cityscapes test-time fit on L_reproj) the objects are predicted once, ordered
    by predicted depth, and refined with each object's crop ignoring the masks of the objects in front of it
    (:func:`occluder_masks`), so that an occluder does not pull the fit.
    """
    windows = torch.tensor([square_crop_window(b, models.margin) for b in boxes], dtype=torch.float32)
    size = models.crop_size
    crops = crop_windows(image, windows, size, "bilinear")
    crop_masks = crop_windows(masks[:, None].float(), windows, size, "nearest")
    n = len(boxes)
    intr_vec = torch.tensor([intr.fx, intr.fy, intr.cx, intr.cy], dtype=torch.float32).expand(n, 4)
    if refine is None:
        return models.geometric.predict(crops * crop_masks, crop_masks, boxes, intr_vec)
    crop_intr = crop_intrinsics(intr, windows, size)
    depth = models.geometric.predict(crops * crop_masks, crop_masks, boxes, intr_vec)["center"][:, 2].cpu()
    ignore = crop_windows(occluder_masks(masks, depth)[:, None].float(), windows, size, "nearest")
    return models.geometric.predict(crops * crop_masks, crop_masks, boxes, intr_vec, crop_intr, ignore, refine)


def occluder_masks(masks: Tensor, depth: Tensor) -> Tensor:
    """``(N, H, W)`` bool: for each object, the pixels of the ``masks (N, H, W)`` of the objects nearer than it
    (``depth (N,)``, e.g. predicted box-centre z), which its silhouette may cover unseen.

    >>> masks = torch.zeros(2, 1, 4, dtype=torch.bool); masks[0, 0, :2] = True; masks[1, 0, 1:] = True
    >>> occluder_masks(masks, torch.tensor([5.0, 9.0]))[:, 0].int().tolist()  # object 0 is in front
    [[0, 0, 0, 0], [1, 1, 0, 0]]
    """
    nearer = (depth[None, :] < depth[:, None]).float()  # (N, N): row i, column j in front of i
    return (nearer @ masks.flatten(1).float()).view(masks.shape) > 0


def _annotation_boxes(gt: GroundTruth, ids: Tensor) -> tuple[Tensor, Tensor]:
    """``(N, 4)`` annotated pixel-centre boxes of the objects ``ids`` and ``(N,)`` bool: found."""
    boxes = torch.zeros(len(ids), 4)
    found = torch.zeros(len(ids), dtype=torch.bool)
    for i, iid in enumerate(ids.tolist()):  # a dict lookup per object, not tensor work
        box = gt.boxes.get(iid % INSTANCE_DIVISOR)
        if box is not None:
            boxes[i] = box
            found[i] = True
    return boxes, found


def _geometry(image: Tensor, intr: Intrinsics, masks: Tensor, ids: Tensor, gt: GroundTruth | None,
              models: Models, min_pixels: int, refine: RefineSettings | None,
              annotated: Tensor | None = None) -> tuple[Tensor, ...]:
    """``template (N,), dims (N, 3), ry (N,), location (N, 3), phi (N, 64, 3)`` of the objects ``masks``
    (template -1 and placeholders for objects without a usable prediction); ``gt``: annotated boxes, looked up
    for the rows ``annotated (N,)`` bool (None: all)."""
    n = len(ids)
    template = torch.full((n,), -1, dtype=torch.long)
    dims, location = torch.ones(n, 3, dtype=torch.float64), torch.zeros(n, 3, dtype=torch.float64)
    location[:, 2] = 1.0
    ry, phi = torch.zeros(n, dtype=torch.float64), torch.zeros(n, 64, 3)
    rows = (masks.flatten(1).sum(1) >= min_pixels).nonzero().flatten()
    if models.geometric is None or not len(rows):
        return template, dims, ry, location, phi
    boxes = pixel_centre_boxes(mask_boxes(masks[rows]))  # the branch encodes pixel-centre boxes
    if gt is not None:
        given, found = _annotation_boxes(gt, ids[rows])
        if annotated is not None:
            found &= annotated[rows]
        boxes = torch.where(found[:, None], given, boxes)
    # The branch's box encoding needs r > l and b > t (a one-pixel-wide sliver has r == l).
    wide = (boxes[:, 2] > boxes[:, 0]) & (boxes[:, 3] > boxes[:, 1])
    rows, boxes = rows[wide], boxes[wide]
    if not len(rows):
        return template, dims, ry, location, phi
    pred = {k: v.detach().cpu() for k, v in _predict_geometry(image, intr, masks[rows], boxes, models, refine).items()}
    ok = (torch.isfinite(pred["dims"]).all(1) & torch.isfinite(pred["location"]).all(1) & torch.isfinite(pred["ry"])
          & torch.isfinite(pred["phi"]).flatten(1).all(1) & (pred["dims"] > 0).all(1) & (pred["center"][:, 2] > 0))
    if not bool(ok.all()):
        log.warning("derender: %d object(s) got no usable 3D prediction and keep their 2D mask", int((~ok).sum()))
    keep = rows[ok]
    template[keep] = pred["template_id"][ok].long()
    dims[keep], location[keep] = pred["dims"][ok].double(), pred["location"][ok].double()
    ry[keep], phi[keep] = pred["ry"][ok].double(), pred["phi"][ok].float()
    return template, dims, ry, location, phi


def _checked_image(image: Tensor, intrinsics: Intrinsics, proposals: str, gt: GroundTruth | None) -> Tensor:
    """``image`` as float32 on the CPU, clamped to ``[0, 1]``, after checking it and its companions."""
    if proposals not in PROPOSALS:
        raise ValueError(f"proposals must be one of {PROPOSALS}, got {proposals!r}")
    if image.dim() != 3 or image.shape[0] != 3 or not image.is_floating_point():
        raise ValueError(f"image must be a float (3, H, W) tensor in [0, 1], got {image.dtype} {tuple(image.shape)}")
    if tuple(image.shape[-2:]) != intrinsics.size:
        raise ValueError(f"image is {image.shape[-1]}x{image.shape[-2]} but intrinsics are for "
                         f"{intrinsics.width}x{intrinsics.height}")
    if not bool(torch.isfinite(image).all()) or float(image.min()) < -1e-3 or float(image.max()) > 1 + 1e-3:
        raise ValueError("image values must be finite and in [0, 1]")
    if gt is not None and tuple(gt.semantic.shape) != intrinsics.size:
        raise ValueError(f"ground_truth is {tuple(gt.semantic.shape)} but the image is {intrinsics.size} (H, W)")
    return image.detach().float().cpu().clamp(0, 1)


def _semantics_and_instances(image: Tensor, models: Models, proposals: str, gt: GroundTruth | None,
                             name: str) -> tuple[Tensor, Tensor, str, str, Segmentation | None]:
    """Steps 1-2 of the module doc: ``(semantic (H, W), instances (H, W), proposal source, semantic source,
    segmentation)`` with sources ``'gt'`` (the oracle), ``'semantic'`` / ``'branch'`` (the semantic branch),
    ``'boxes'`` (no proposal but the boxes) and ``'none'`` (no semantics: every pixel 255, ignore);
    ``segmentation``: the branch's output where it ran, else None."""
    class_list = CLASS_LISTS[name]
    height, width = image.shape[-2:]
    if proposals == "boxes":  # the boxes alone; semantics from the branch, else the ground truth, else none
        if models.semantic is not None:
            _check_class_count(models, class_list, name)
            seg = models.semantic(image)
            return seg.label[0].cpu(), torch.zeros(height, width, dtype=torch.long), "boxes", "branch", seg
        semantic = gt.semantic if gt is not None else torch.full((height, width), 255, dtype=torch.long)
        return semantic, torch.zeros(height, width, dtype=torch.long), "boxes", "gt" if gt is not None else "none", None
    use_branch = proposals == "semantic" or (proposals == "auto" and models.semantic is not None)
    use_gt_masks = proposals == "gt" or (proposals == "auto" and gt is not None and gt.instances is not None)
    if (use_branch or not use_gt_masks) and models.semantic is None:
        raise UserInputError(f"proposals={proposals!r} needs a semantic model"
                             + ("" if use_branch else " (no ground truth with an instance map was given)"))
    if (not use_branch or use_gt_masks) and gt is None:
        raise UserInputError(f"proposals={proposals!r} needs the frame's ground truth (ground_truth=)")
    gt_semantic = gt_instances = None
    if gt is not None and (not use_branch or use_gt_masks):
        gt_semantic, gt_instances = gt.semantic, gt.instances
        if use_gt_masks and gt_instances is None:
            raise UserInputError(f"proposals={proposals!r}: ground truth {gt.key} has no instance map")
    seg = None
    if use_branch or not use_gt_masks:
        _check_class_count(models, class_list, name)
        seg = models.semantic(image)
    semantic = seg.label[0].cpu() if use_branch else gt_semantic
    instances, source = (gt_instances, "gt") if use_gt_masks else (seg.instance[0].cpu(), "semantic")
    return semantic, instances, source, "branch" if use_branch else "gt", seg


def _check_class_count(models: Models, class_list: tuple, name: str) -> None:
    if len(models.semantic.classes) != len(class_list):
        raise UserInputError(f"the semantic model predicts {len(models.semantic.classes)} classes, the scene's "
                             f"class list {name!r} has {len(class_list)}")


def _add_boxes(image: Tensor, masks: Tensor, ids: Tensor, boxes: BoxPrompts, seg: Segmentation | None,
               things: Tensor, class_list: Sequence[SemanticClass]) -> tuple[Tensor, Tensor, Tensor, list[str]]:
    """``(masks, ids, box_rows, each box's mask source)``: the proposals with the box objects' GrabCut masks appended
    (they take their pixels from the other proposals; a proposal left with less than half its pixels is dropped)."""
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
        source = ["given"] * len(boxes)
    else:
        box_masks, from_box = grabcut_masks(image, boxes.boxes, prior=prior, iterations=boxes.iterations)
        grabcut = "grabcut, seeded by the semantic branch" if prior is not None else "grabcut"
        source = ["the whole box (GrabCut found too little in it)" if f else grabcut for f in from_box.tolist()]
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


def _fit_boxes(intr: Intrinsics, masks: Tensor, rows: Tensor, boxes: BoxPrompts, geometry: tuple[Tensor, ...],
               min_pixels: int) -> tuple[tuple[Tensor, ...], list[dict]]:
    """The geometry with the box objects' rows fitted to their masks (:func:`~sdn3d.geometric.fit.fit_to_masks`,
    the geometric branch's prediction as the start) and per box its record for ``meta['boxes']``."""
    from sdn3d.box_masks import nearest_first
    from sdn3d.geometric.fit import fit_to_masks

    template, dims, ry, location, phi = (g.clone() for g in geometry)
    settings = boxes.fit
    pixels = masks[rows].flatten(1).sum(1)
    fitted = pixels >= min_pixels
    predicted = template[rows] >= 0
    order = nearest_first(boxes.boxes)
    rank = torch.empty_like(order)
    rank[order] = torch.arange(len(order))
    # What may hide box i: every other proposal, and the boxes nearer than it (the farther ones it hides).
    others = torch.ones(len(masks), dtype=torch.bool)
    others[rows] = False
    rest = masks[others].any(0) if bool(others.any()) else torch.zeros_like(masks[0])
    ignore = occluder_masks(masks[rows], rank.float()) | rest
    result = None
    sel = fitted.nonzero().flatten()
    if len(sel):
        start_ry = torch.where(predicted[sel], ry[rows[sel]].float(), torch.full((len(sel),), float("nan")))
        start_dims = torch.where(predicted[sel, None], dims[rows[sel]].float(), torch.full((len(sel), 3), float("nan")))
        start_location = torch.where(predicted[sel, None], location[rows[sel]].float(),
                                     torch.full((len(sel), 3), float("nan")))
        result = fit_to_masks(masks[rows[sel]], boxes.boxes[sel], intr, ignore=ignore[sel], start_ry=start_ry,
                              start_dims=start_dims, start_template=template[rows[sel]], start_location=start_location,
                              settings=settings)
        target = rows[sel]
        template[target] = result.template
        dims[target], ry[target] = result.dims.double(), result.ry.double()
        location[target], phi[target] = result.location.double(), result.phi.float()
    records, iou = [], dict(zip(sel.tolist(), result.iou.tolist(), strict=True)) if result is not None else {}
    for i in range(len(boxes)):
        fit_iou = iou.get(i)
        record = {"box": [round(float(v), 2) for v in boxes.boxes[i]], "mask_pixels": int(pixels[i]),
                  "pose": ("fitted to the mask from the geometric branch's prediction" if bool(predicted[i])
                           else "fitted to the mask from the box on the road plane") if fit_iou is not None else None,
                  "fit_iou": None if fit_iou is None else round(fit_iou, 4),
                  "poor_fit": fit_iou is None or fit_iou < settings.poor_iou}
        if fit_iou is None:
            record["why"] = f"its mask has {int(pixels[i])} pixels (< min_pixels {min_pixels}): no 3D fit"
            template[rows[i]] = -1
        records.append(record)
    return (template, dims, ry, location, phi), records


def _refine_box_masks(image: Tensor, intr: Intrinsics, masks: Tensor, rows: Tensor, boxes: BoxPrompts,
                      geometry: tuple[Tensor, ...], records: list[dict]) -> tuple[Tensor, list[bool]]:
    """``(masks, each box's mask segmented again?)``: the box objects' GrabCut masks segmented again, seeded by
    their fitted 3D shapes drawn in the image (:func:`~sdn3d.box_masks.refine_with_silhouettes`), for the boxes
    whose fit matched its mask; ``records[i]['mask_pixels']`` follows."""
    from sdn3d.box_masks import refine_with_silhouettes
    from sdn3d.math3d.transforms import bottom_to_center
    from sdn3d.render import RasterSettings, rasterize_meshes
    from sdn3d.render.objects import pose_meshes

    good = torch.tensor([r["fit_iou"] is not None and not r["poor_fit"] for r in records], dtype=torch.bool)
    if not bool(good.any()):
        return masks, [False] * len(records)
    template, dims, ry, location, phi = (g[rows[good]] for g in geometry)
    center = bottom_to_center(location, dims[:, 1])
    verts, faces = pose_meshes(default_bank(), template, dims.float(), ry.float(), center.float(), phi.float())
    drawn = torch.zeros(len(records), *masks.shape[-2:], dtype=torch.bool)
    drawn[good] = rasterize_meshes(verts, faces, intr.matrix().float(), RasterSettings(tuple(masks.shape[-2:]))).mask
    others = torch.ones(len(masks), dtype=torch.bool)
    others[rows] = False
    again = refine_with_silhouettes(image, boxes.boxes, masks[rows], drawn, refine=good,
                                    others=masks[others].any(0) if bool(others.any()) else None,
                                    iterations=boxes.iterations)
    masks = masks.clone()
    masks[rows] = again
    for record, mask in zip(records, again, strict=True):
        record["mask_pixels"] = int(mask.sum())
    return masks, good.tolist()


def derender(image: Tensor, intrinsics: Intrinsics, models: Models, proposals: str = "auto",
             ground_truth: GroundTruth | None = None, *, classes: str | None = None, min_pixels: int = 64,
             refine: RefineSettings | None = None, boxes: BoxPrompts | None = None) -> SceneCode:
    """De-render ``image (3, H, W)`` float in ``[0, 1]`` into a scene (module doc).

    Args:
        image: the image at the working size; ``intrinsics`` must be of that size.
        models: the branches (None ones are skipped; see ``proposals``).
        proposals: ``'auto'``: semantic map from the semantic branch (the ground truth's without one),
            masks from the ground-truth instance map if there is one, else the branch's instance head;
            ``'gt'``: semantic map and masks from ``ground_truth`` (an oracle); ``'semantic'``: both from
            the semantic branch; ``'boxes'``: the objects are ``boxes`` alone (semantics from the branch, else
            the ground truth, else none: 255).
        ground_truth: the frame's ground truth at the working size (oracle maps and annotated boxes),
            optional; :func:`sdn3d.data.scene_gt.ground_truth` builds it from a dataset frame.
        classes: class list name (default: from the ground truth or the models).
        min_pixels: visible pixels (at the working size) an object needs to get 3D geometry.
        refine: optional reprojection refinement of the geometric predictions (Cityscapes setting).
        boxes: objects named by a box, added to (or, ``'boxes'``, instead of) the proposals.

    Raises:
        ValueError: bad image / intrinsics or an unknown ``proposals`` (the caller's mistake).
        UserInputError (a ValueError): no source for the semantic map or the proposals, a semantic
            model of another class list (the user's settings or checkpoints), or ``'boxes'`` without boxes.
    """
    gt = ground_truth
    image = _checked_image(image, intrinsics, proposals, gt)
    if proposals == "boxes" and (boxes is None or not len(boxes)):
        raise UserInputError("proposals='boxes' needs objects given by a box (an edit spec's `objects:`)")
    name = _class_list_name(models, gt, classes)
    class_list = CLASS_LISTS[name]
    semantic, instances, source, semantic_source, seg = _semantics_and_instances(image, models, proposals, gt, name)

    # Proposals: ids of instance classes only (a scene's objects must be things).
    things = torch.tensor([c.id for c in class_list if c.has_instances], dtype=torch.long)
    ids = instances.unique()
    ids = ids[(ids >= INSTANCE_DIVISOR) & torch.isin(ids // INSTANCE_DIVISOR, things)]
    masks = instances[None] == ids[:, None, None]  # (N, H, W)
    box_rows, box_records, mask_source = torch.zeros(0, dtype=torch.long), [], None
    if boxes is not None and len(boxes):
        masks, ids, box_rows, mask_source = _add_boxes(image, masks, ids, boxes, seg, things,
                                                       class_list)
    n = len(ids)
    annotated = torch.ones(n, dtype=torch.bool)
    annotated[box_rows] = False
    geometry = _geometry(image, intrinsics, masks, ids, gt if source == "gt" else None, models, min_pixels, refine,
                         annotated)
    if len(box_rows):
        geometry, box_records = _fit_boxes(intrinsics, masks, box_rows, boxes, geometry, min_pixels)
        if boxes.masks is None and boxes.refine_masks:
            first = masks[box_rows].any(0)  # what the second masks leave of it is no object's
            masks, again = _refine_box_masks(image, intrinsics, masks, box_rows, boxes, geometry, box_records)
            instances = torch.where(first, torch.zeros_like(instances), instances)
            mask_source = [m + ", then again seeded by its fitted 3D shape" if a else m
                           for m, a in zip(mask_source, again, strict=True)]
        for record, iid, mask in zip(box_records, ids[box_rows].tolist(), mask_source, strict=True):
            record["id"] = int(iid)
            record["mask"] = mask
        instances = torch.where(masks.any(0), (masks.long() * ids[:, None, None]).sum(0), instances)
    semantic = torch.where(masks.any(0), (instances // INSTANCE_DIVISOR), semantic)
    template, dims, ry, location, phi = geometry
    geo = template >= 0
    code_dim = models.textural.spec.code_dim if models.textural is not None else DEFAULT_CODE_DIM
    table = ObjectTable(instance_id=ids, template_id=template, phi=phi, dims=dims, ry=ry, location=location,
                        code=torch.zeros(n, code_dim), mask=masks, has_mask=torch.ones(n, dtype=torch.bool),
                        observed=torch.ones(n, dtype=torch.bool))
    meta = {"source": gt.key if gt is not None else "image", "proposals": source,
            "semantic": semantic_source,
            "objects": n, "with_geometry": int(geo.sum()), "crop_size": models.crop_size, "min_pixels": min_pixels}
    if box_records:
        meta["boxes"] = box_records
        meta["fit"] = boxes.fit.to_dict()
    scene = SceneCode(intrinsics, semantic, name, table, torch.zeros(len(class_list), code_dim), meta)
    if models.textural is None:
        return scene
    L = torch.where(masks.any(0), instances, semantic)  # dropped (non-thing) proposals count as background
    return encode_scene(scene, image, models.textural, L)


def encode_scene(scene: SceneCode, image: Tensor, textural: TexturalRenderer, L: Tensor | None = None,
                 bank: MeshBank | None = None) -> SceneCode:
    """The scene with the texture codes the encoder pools from ``image (3, H, W)`` over ``L``.

    Args:
        L: ``(H, W)`` instance label map of the image; None: the scene's composed one
            (:func:`~sdn3d.scene.maps.scene_maps`, e.g. for :meth:`SceneCode.from_frame` scenes).

    Objects absent from ``L`` and classes without pixels get zero codes.
    """
    if L is None:
        L = scene_maps(scene, bank).instance_label_map.cpu()
    if tuple(L.shape) != scene.intrinsics.size or tuple(image.shape) != (3, *scene.intrinsics.size):
        raise ValueError(f"image (3, H, W) and L (H, W) must have the scene's size {scene.intrinsics.size}, got "
                         f"{tuple(image.shape)} and {tuple(L.shape)}")
    dev = textural.device
    codes = textural.encode(image[None].to(dev, torch.float32), L[None].to(dev))
    ids, values = codes.ids.cpu(), codes.codes.detach().float().cpu()
    obj = scene.objects
    hit = (obj.instance_id[:, None] == ids[None]).float()  # (N, R): at most one region per object
    object_codes = hit @ values
    num = len(scene.class_list)
    background = torch.zeros(num, values.shape[1])
    sel = ids < num
    background[ids[sel]] = values[sel]
    return scene.replace(objects=obj.replace(code=object_codes), background_codes=background)
