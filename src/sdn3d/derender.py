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
   (:meth:`GeometricPredictor.predict`): template, FFD ``phi``, dims, yaw, location. Given the ``photo`` the
   working image was made from (:class:`~sdn3d.image_ops.InputPhoto`), the crops are read from it at its own
   resolution (antialiased; the masks from the working size over the same windows), so a small object's crop, and
   the red-lamp cue that reads it, keeps the photo's detail (issue 40); the lamp cue then reads only the crop
   pixels surely on the object (:data:`SURE_MASK`: a working mask pixel covers several photo pixels, part
   background at its edge, where a neighbour's tail light or a red wall would count). The semantic branch's masks
   often stop above a car's bottom, and so above its tail lamps at the back's corners (on tuning seed 31's clone
   frames the lamps lay just under the mask of 10 of 41 turned cars, read as "no red lamps: a front", and the fit
   turned them end for end): for its proposals, where the mask shows no usable red lamps, the red tail-lamp test
   reads the mask and the band under it that the fit counts as unsure (:func:`~sdn3d.proposal_fit.unsure_below`);
   a mask that shows usable red lamps is read as before, and a red body's headlight test never reads the band (its
   road reads near-white through rain; ``docs/results/2026-11-29_cpu/session10/semflip``). The semantic branch's masks
   also spill past a car onto the road, a lane marking, a sign above it, and the lamp cue read those pixels: a lane
   marking beside a red van's lower half as its "headlights", a red sign above a car as a second band of red that made
   its tail lamps unusable (on the Table 1 tuning trees 31, 35 and 37, session 21's demo weights, the fit turned 33 of
   279 matched proposals end for end, 26 of them cars it did not turn on their ground-truth masks (an oracle), and 20 of
   those 26 read their lamps otherwise on the proposal than on the true mask). So with ``fit`` each fitted proposal (not
   a poor fit) has its lamps read again on the part of its mask that its fitted 3D shape covers, the tail band cut to
   that shape too (:func:`_lamps_on_fits`), and the proposals whose reading changed (a test's present or usable flag)
   are chosen again with it among the first fit's hypotheses (:func:`~sdn3d.proposal_fit.choose_proposals_again`:
   what fitting them again from their prediction gives, as the hypotheses and their fits do not read the belief,
   without the second fit's cost): the fit's hypotheses all lie on the silhouette's axis, so their shape is where the
   car is whichever end it faces (``docs/results/2026-11-30_cpu/session24/predflip``). The 2D box is
   the annotation's when the object comes from a ground-truth frame (what the branch is trained
   on), else the mask's bounding box. Objects without a prediction (no geometric model, too small,
   a box one pixel wide or high, non-finite output or behind the camera) keep only their 2D mask.
   A box object's prediction (when there is a geometric branch) only starts :func:`~sdn3d.geometric.fit.fit_to_masks`:
   every template and four yaws fitted to its mask on the road plane, other objects' pixels ignored (the box
   sub-pipeline is :mod:`sdn3d.box_objects`); the scene's ``meta['boxes']`` holds per box its
   :class:`~sdn3d.box_objects.BoxFit`: where its mask and pose came from and the fit's silhouette IoU. With
   ``fit`` the proposals' vehicles get the same fit (:mod:`sdn3d.proposal_fit`; ``meta['fits']``): the edit
   path's default, while ``fit=None`` keeps the branch's predictions (the paper's protocol). The semantic branch's
   proposals whose masks touch and whose fitted cars share the ground (``FitSettings.join_overlap``;
   :func:`~sdn3d.proposal_fit.footprint_joins`: one car cut in parts) are then joined under the largest part's id,
   and the objects go through this step once more (the joined car fitted as one; its record's ``joined_from``): the
   geometric branch on every object (one forward; each object's prediction is its own whatever the batch,
   :data:`~sdn3d.geometric.predict.MIN_NET_ROWS`, and its bits are compared, not assumed), the fit only on the joined
   cars and the proposals whose fit reads anything else than in the first pass (the bits of its prediction, or the
   pixels it is fitted without in its windows: a joined car's new depth may put its parts' pixels in front of it or
   behind it, :func:`~sdn3d.proposal_fit.proposal_ignore`); the others keep their first fit, what a second one gives
   (the objects are fitted independently, up to the last bit of a yaw). A camera height measured from every prediction
   (``FitSettings.camera_height=None``) fits all of them again (``docs/results/2026-12-01_cpu/session29/joincost29``).
4. **Texture**: the textural encoder pools one code per region of the instance label map ``L``
   (objects and background classes): :func:`encode_scene`.

Every object is *observed* and keeps its visible mask, so rendering an unedited scene redraws the
image's own layout; edits (:func:`sdn3d.editing.apply.apply_edits`) free the masks of moved objects.
Drawing a scene and editing an image end to end are :mod:`sdn3d.editing.render`.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import torch
from torch import Tensor

from sdn3d.box_objects import (
    BoxPrompts,
    add_box_objects,
    box_grabcut,
    box_request,
    fit_box_objects,
    fitted_silhouettes,
    occluder_masks,
)
from sdn3d.errors import UserInputError
from sdn3d.image_ops import (
    InputPhoto,
    crop_intrinsics,
    crop_windows,
    mask_boxes,
    pixel_centre_boxes,
    square_crop_window,
)
from sdn3d.labels import CLASS_LISTS, INSTANCE_DIVISOR
from sdn3d.math3d.camera import Intrinsics
from sdn3d.meshes.bank import MeshBank
from sdn3d.models import Models
from sdn3d.proposal_fit import (
    ProposalFit,
    choose_proposals_again,
    fit_proposals,
    fit_proposals_and_boxes,
    footprint_joins,
    join_masks,
    proposal_ignore,
    unsure_below,
    vehicle_rows,
)
from sdn3d.proposals import PROPOSALS, Proposals, choose_sources
from sdn3d.road_heading import road_axes
from sdn3d.scene.code import DEFAULT_CODE_DIM, ObjectTable, SceneCode
from sdn3d.scene.maps import scene_maps

if TYPE_CHECKING:
    from sdn3d.geometric.facing import Appearance
    from sdn3d.geometric.fit import FitResult, FitSettings
    from sdn3d.geometric.refine import RefineSettings
    from sdn3d.semantic.predict import Segmentation
    from sdn3d.textural.renderer import TexturalRenderer

__all__ = [
    "PROPOSALS",
    "Proposals",
    "PROPOSAL_LABELS",
    "BoxPrompts",
    "GroundTruth",
    "derender",
    "encode_scene",
    "occluder_masks",
]

log = logging.getLogger(__name__)

#: With a photo, a crop pixel is surely on the object (the lamp cue reads it) where the working mask's bilinear
#: sample there is at least this: every working pixel it reads is the object's, half a working pixel in from the
#: mask's edge. On the seed-13 tuning tree (146 cars and vans over 64 pixels at 312x96, ground-truth masks, the demo's
#: branch) the photo's crops flipped 15 cars end for end with the whole mask and 5 with this (0.9: 9; 0.75: 11).
SURE_MASK = 0.999

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
                      refine: RefineSettings | None, photo: InputPhoto | None = None,
                      tail: Tensor | None = None) -> dict[str, Tensor]:
    """Batched geometric branch on the objects ``masks (N, H, W)`` with 2D ``boxes (N, 4)``; the crops of the
    working ``image`` or, given, of the ``photo`` it was made from (the same windows). ``tail``: ``(N, H, W)`` bool
    pixels past each mask that the red tail-lamp test reads too (the predictor's ``tail_mask``; None: none).

    With ``refine`` (the paper's Cityscapes test-time fit on L_reproj) the objects are predicted once, ordered
    by predicted depth, and refined with each object's crop ignoring the masks of the objects in front of it
    (:func:`occluder_masks`), so that an occluder does not pull the fit.
    """
    windows, size = _windows(boxes, models), models.crop_size
    crops = crop_windows(image, windows, size, "bilinear") if photo is None else photo.crops(windows, size)
    crop_masks = crop_windows(masks[:, None].float(), windows, size, "nearest")
    sure, tail_mask = _lamp_masks(masks, tail, windows, size, photo)
    # The crops go in masked, as the net sees them; with a tail band unmasked (the predictor masks the net's input
    # itself), so that the tail-lamp test can read past the mask.
    given, lamps = crops * crop_masks, {"lamp_mask": sure, "image_width": intr.width}
    if tail is not None:
        given, lamps["tail_mask"] = crops, tail_mask
    n = len(boxes)
    intr_vec = torch.tensor([intr.fx, intr.fy, intr.cx, intr.cy], dtype=torch.float32).expand(n, 4)
    if refine is None:
        return models.geometric.predict(given, crop_masks, boxes, intr_vec, **lamps)
    crop_intr = crop_intrinsics(intr, windows, size)
    depth = models.geometric.predict(given, crop_masks, boxes, intr_vec, **lamps)["center"][:, 2].cpu()
    ignore = crop_windows(occluder_masks(masks, depth)[:, None].float(), windows, size, "nearest")
    return models.geometric.predict(given, crop_masks, boxes, intr_vec, crop_intr, ignore, refine, **lamps)


def _windows(boxes: Tensor, models: Models) -> Tensor:
    """``(N, 3)`` the geometric branch's square crop windows ``(left, top, side)`` around ``boxes (N, 4)``."""
    return torch.tensor([square_crop_window(b, models.margin) for b in boxes], dtype=torch.float32)


def _lamp_masks(masks: Tensor, tail: Tensor | None, windows: Tensor, size: int, photo: InputPhoto | None
                ) -> tuple[Tensor | None, Tensor | None]:
    """``(lamp_mask, tail_mask)``: the ``(N, 1, S, S)`` crop pixels of ``windows`` that the lamp cue reads of the
    ``masks (N, H, W)`` (with a photo the pixels surely on the object, :data:`SURE_MASK`; None without one: the
    predictor's nearest mask) and, with ``tail (N, H, W)``, of each mask and its tail band (the same rule, nearest
    without a photo; None without a band)."""
    sure = (None if photo is None else
            (crop_windows(masks[:, None].float(), windows, size, "bilinear") >= SURE_MASK).float())
    if tail is None:
        return sure, None
    grown = (masks | tail)[:, None].float()
    return sure, (crop_windows(grown, windows, size, "nearest") if photo is None else
                  (crop_windows(grown, windows, size, "bilinear") >= SURE_MASK).float())


def _lamps_on_fits(image: Tensor, intr: Intrinsics, masks: Tensor, tail: Tensor | None, rows: Tensor,
                   fitted: tuple[Tensor, ...], appearance: Appearance, models: Models,
                   photo: InputPhoto | None) -> tuple[Appearance, Tensor]:
    """``(appearance, changed)``: ``appearance`` with the lamps of the fitted proposals ``rows (K,)`` read again on
    the part of each mask that its fitted 3D shape (``fitted``: the geometry after the fit) covers, and ``(M,)`` the
    rows whose reading changed (a red or white test's present or usable flag): the ones to choose again (module
    doc, step 3). The crops are the branch's (the windows of the masks' boxes, as :func:`_geometry` reads them);
    ``tail (N, H, W)``: the band under each mask the red test also reads, cut to the fitted shape as well."""
    from sdn3d.geometric.facing import Appearance
    from sdn3d.geometric.lamps import read_lamps

    if not len(rows):
        return appearance, rows
    shape = fitted_silhouettes(intr, fitted, rows)  # (K, H, W)
    agreed = masks[rows] & shape
    boxes = pixel_centre_boxes(mask_boxes(masks[rows]))
    windows, size = _windows(boxes, models), models.crop_size
    crops = crop_windows(image, windows, size, "bilinear") if photo is None else photo.crops(windows, size)
    crop_masks = crop_windows(masks[rows][:, None].float(), windows, size, "nearest")
    near = crop_windows(agreed[:, None].float(), windows, size, "nearest")
    sure, tail_mask = _lamp_masks(agreed, None if tail is None else tail[rows] & shape, windows, size, photo)
    red, white = read_lamps(crops * crop_masks, near if sure is None else sure, models.geometric.lamp_cue, crops,
                            tail_mask)
    values = dict(appearance.values)
    changed = torch.zeros(len(rows), dtype=torch.bool)
    for keys, reading in ((("lamp_present", "lamp_usable", "lamp_offset"), red),
                          (("front_present", "front_usable", "front_offset"), white)):
        if keys[0] not in values:
            continue
        for k, v in zip(keys, reading, strict=True):
            old = values[k][rows]
            if v.dtype == torch.bool:
                changed |= v.cpu() != old
            values[k] = values[k].clone()
            values[k][rows] = v.cpu().to(old.dtype)
    return Appearance(values, appearance.has, appearance.cue), rows[changed]


def _choose_on_agreed_lamps(image: Tensor, intr: Intrinsics, masks: Tensor, ids: Tensor, rows: Tensor,
                            first: FitResult, fitted: tuple[Tensor, ...], records: list[ProposalFit],
                            fit: FitSettings, appearance: Appearance, unsure: Tensor | None, models: Models,
                            photo: InputPhoto | None) -> tuple[tuple[Tensor, ...], list[ProposalFit]]:
    """``(geometry, records)``: the proposals' fit (``first``, its geometry ``fitted`` and ``records``: one per row of
    ``rows (K,)``) with the proposals whose lamps read otherwise on the part of their mask that their fitted shape
    covers (:func:`_lamps_on_fits`; a poor fit's shape is not trusted) chosen again among the first fit's hypotheses
    under that reading (:func:`~sdn3d.proposal_fit.choose_proposals_again`: what fitting them again gives, on the road
    the first fit measured; module doc, step 3)."""
    good = {r.instance_id for r in records if not r.poor}
    trusted = torch.tensor([int(i) in good for i in ids[rows].tolist()], dtype=torch.bool)
    reread, again = _lamps_on_fits(image, intr, masks, unsure, rows[trusted], fitted, appearance, models, photo)
    if not len(again):
        return fitted, records
    geometry, new = choose_proposals_again(first, ids, rows, again, fitted, fit, reread)
    by_id = {r.instance_id: r for r in new}
    return geometry, [by_id.get(r.instance_id, r) for r in records]


@dataclass(frozen=True)
class _Objects:
    """Step 3 of the module doc for ``N`` objects (:func:`_objects_3d`).

    Attributes:
        predicted: the geometric branch's geometry ``template (N,), dims (N, 3), ry (N,), location (N, 3), phi (N, 64,
            3)`` (template -1 and placeholders for objects without a usable prediction).
        geometry: the same after the proposals' fit (``predicted`` without ``fit``).
        appearance: what the branch saw of each object (:func:`_geometry`), None without a lamp cue.
        fits: the fitted proposals' records, in row order.
        box_result: the box objects' share of a fit made with the proposals' (else None); box_axes: ``(B,)`` the
            road's axis at each box object that fit was asked with (NaN: unknown; None: none).
        band: ``(N, H, W)`` bool the band under each mask that the fit ignores
            (:func:`~sdn3d.proposal_fit.unsure_below`; None: none, or no fit).
        ignore: ``(N, H, W)`` bool the pixels each proposal is fitted without, of those its fit reads
            (:func:`~sdn3d.proposal_fit.proposal_ignore` with the fit's settings: all its fit reads of the other
            objects); only once :meth:`with_ignore` made it (a join's first pass), else None.
    """

    predicted: tuple[Tensor, ...]
    geometry: tuple[Tensor, ...]
    appearance: Appearance | None
    fits: list[ProposalFit]
    box_result: FitResult | None
    band: Tensor | None
    ignore: Tensor | None = None
    box_axes: Tensor | None = None

    def rows(self, index: Tensor) -> _Objects:
        """These objects' results for the rows ``index (M,)`` (the records and the box objects' fit as they are)."""
        return _Objects(tuple(g[index] for g in self.predicted), tuple(g[index] for g in self.geometry),
                        None if self.appearance is None else self.appearance.rows(index), self.fits, self.box_result,
                        None if self.band is None else self.band[index],
                        None if self.ignore is None else self.ignore[index], self.box_axes)

    def with_ignore(self, masks: Tensor, fit: FitSettings) -> _Objects:
        """These objects with their :attr:`ignore` for their ``masks (N, H, W)`` and the ``fit``'s settings: made
        only where a join needs it, not on every de-render."""
        return replace(self, ignore=proposal_ignore(masks, self.predicted, self.band, fit))


_INT_OF = {torch.float64: torch.int64, torch.float32: torch.int32, torch.float16: torch.int16}


def _same_bits(a: Tensor, b: Tensor) -> Tensor:
    """``(N,)`` bool: the rows of ``a`` and ``b`` (``(N, ...)``, one shape and dtype) that hold the same bits (so -0.0
    is not 0.0 and a NaN is itself: a fit started from either may go its own way)."""
    if a.is_floating_point():
        a, b = a.contiguous().view(_INT_OF[a.dtype]), b.contiguous().view(_INT_OF[b.dtype])
    return (a == b).reshape(len(a), -1).all(1)


def _same_prediction(predicted: tuple[Tensor, ...], appearance: Appearance | None, earlier: _Objects) -> Tensor:
    """``(N,)`` bool: the rows whose geometric prediction (``predicted``: template, dims, ry, location, phi) and
    ``appearance`` hold the same bits as ``earlier``'s (the same rows)."""
    same = torch.ones(len(predicted[0]), dtype=torch.bool)
    for now, before in zip(predicted, earlier.predicted, strict=True):
        same &= _same_bits(now, before)
    if (appearance is None) != (earlier.appearance is None):
        return torch.zeros_like(same)
    if appearance is not None:
        same &= _same_bits(appearance.has, earlier.appearance.has)
        for k, v in appearance.values.items():
            same &= _same_bits(v, earlier.appearance.values[k])
    return same


def _objects_3d(masks: Tensor, ids: Tensor, box_rows: Tensor, image: Tensor, intrinsics: Intrinsics, source: str,
                gt: GroundTruth | None, models: Models, min_pixels: int, refine: RefineSettings | None,
                photo: InputPhoto | None, boxes: BoxPrompts | None, fit: FitSettings | None,
                class_names: dict[int, str], unsure_pixels: Tensor | None = None, earlier: _Objects | None = None,
                same: Tensor | None = None) -> _Objects:
    """Step 3 of the module doc for the objects ``masks (N, H, W)``, ``ids (N,)`` (``box_rows (B,)``: those named by
    a box). ``unsure_pixels (H, W)``: the pixels the proposals' silhouette loss leaves out (None: none;
    :attr:`~sdn3d.geometric.fit.FitSettings.unsure_vehicle`).

    ``earlier``: these objects' results from a first pass (derender's join: :meth:`_Objects.rows` of its
    :meth:`_Objects.with_ignore`, the rows ``same (N,)`` bool those whose mask the join left as it was). The geometric
    branch runs on every object again (one forward; each object's prediction is its own whatever the batch,
    :data:`~sdn3d.geometric.predict.MIN_NET_ROWS`, and its bits are compared, not assumed), and a proposal whose fit
    reads the same bits as in the first pass (its mask, its prediction and what the branch saw, the pixels it is fitted
    without: :func:`~sdn3d.proposal_fit.proposal_ignore`) keeps its first fit and record: objects are fitted
    independently (:func:`~sdn3d.geometric.fit.fit_many`). Where a fit reads every object (a camera height measured from
    all the predictions), all are fitted again."""
    n = len(ids)
    annotated = torch.ones(n, dtype=torch.bool)
    annotated[box_rows] = False
    # The semantic branch's masks may stop short of the car's bottom (proposal_fit's module doc), and with it above
    # its tail lamps: where a mask shows none usable, the red-lamp test reads the band under it (module doc, step 3);
    # the ground truth's masks (an oracle) and the boxes' GrabCut masks are taken as they are.
    unsure = unsure_below(masks) if source == "semantic" else None
    if unsure is not None:
        unsure[box_rows] = False
    geometry, appearance = _geometry(image, intrinsics, masks, ids, gt if source == "gt" else None, models,
                                     min_pixels, refine, annotated, photo, unsure)
    predicted, proposal_fits, box_result, band, box_axes = geometry, [], None, None, None
    classes = [class_names.get(int(i) // INSTANCE_DIVISOR) for i in ids]  # each object's: it bounds its templates
    if fit is not None:
        rows = vehicle_rows(ids, geometry[0], class_names)
        rows = rows[~torch.isin(rows, box_rows)]
        band = unsure if len(rows) else None  # the fit ignores the same band
        kept = torch.zeros(n, dtype=torch.bool)  # the rows whose fit reads what it read in the first pass
        read = None if earlier is None else same & _same_prediction(predicted, appearance, earlier)
        # A camera height measured from every prediction, or a box object's prediction that changed (the box
        # objects' fit is made with the proposals'; the masks' union it reads is the same): everything fitted again.
        if read is not None and (fit.camera_height is None or not bool(read[box_rows].all())):
            earlier = None
        if earlier is not None:
            kept = read & _same_bits(proposal_ignore(masks, predicted, band, fit), earlier.ignore)
        refit = rows[~kept[rows]]
        # The lane prior's weight: the semantic branch's rounded outlines are pulled harder than sharp ones (the
        # ground truth's masks here, the box objects'); the box objects' axes are read here when fitted with these.
        lane = fit.proposal_lane_reg if source == "semantic" else fit.lane_reg
        joint = bool(len(refit) and len(box_rows) and boxes.fit == fit and earlier is None)
        lane_rows = torch.cat([refit if lane else refit[:0], box_rows if joint and fit.lane_reg else box_rows[:0]])
        axes = _road_axes(image, intrinsics, masks, lane_rows) if len(lane_rows) else None
        road = axes if lane and len(refit) else None
        box_axes = axes[box_rows] if joint and fit.lane_reg else None
        box_req = (box_request(masks, box_rows, boxes, geometry, min_pixels, appearance, classes, box_axes)
                   if joint else None)
        if box_req is not None:  # one fit for both (the same settings): each stage's fixed cost once
            geometry, proposal_fits, first, box_result = fit_proposals_and_boxes(
                intrinsics, masks, ids, refit, geometry, fit, appearance, box_req, band, classes, unsure_pixels, road,
                lane)
        else:
            geometry, proposal_fits, first = fit_proposals(intrinsics, masks, ids, refit, geometry, fit, appearance,
                                                           band, classes, unsure_pixels, road, lane)
        if source == "semantic" and appearance is not None and fit.appearance and first is not None:
            geometry, proposal_fits = _choose_on_agreed_lamps(image, intrinsics, masks, ids, refit, first, geometry,
                                                              proposal_fits, fit, appearance, band, models, photo)
        if road is not None:  # the records as the lamps' choice left them
            proposal_fits = _with_road(proposal_fits, ids, road)
        if earlier is not None:  # the kept rows' fits and records, and the box objects' fit
            geometry = tuple(torch.where(kept.view(-1, *[1] * (g.dim() - 1)), e, g)
                             for g, e in zip(geometry, earlier.geometry, strict=True))
            by_id = {r.instance_id: r for r in earlier.fits} | {r.instance_id: r for r in proposal_fits}
            proposal_fits = [by_id[i] for i in ids[rows].tolist()]
            box_result = earlier.box_result if len(rows) else None
            box_axes = earlier.box_axes if len(rows) else None
    return _Objects(predicted, geometry, appearance, proposal_fits, box_result, band, box_axes=box_axes)


def _road_axes(image: Tensor, intrinsics: Intrinsics, masks: Tensor, rows: Tensor) -> Tensor:
    """``(N,)`` the road's axis where each of the objects ``rows (K,)`` of ``masks (N, H, W)`` stands
    (:func:`~sdn3d.road_heading.road_axes`, every object's pixels left out of the vote), NaN for the other rows: the
    fit is drawn towards it. A proposal's rounded outline fits many yaws about equally well, and the branch's poor
    prediction chose among them (docs/results/2026-12-02_cpu/session37/lead/edgeband); a car seen end-on casts
    nearly the same outline at any yaw near its own, whatever its mask; on Virtual KITTI's streets, as on real ones,
    nearly every car stands along its lane. The ground truth's masks and the box objects' (GrabCut's) outlines are
    sharp enough to tell some cars parked askew, so they are pulled less
    (:attr:`~sdn3d.geometric.fit.FitSettings.lane_reg` against ``proposal_lane_reg``;
    docs/results/2026-12-02_cpu/session38/lane, docs/results/2026-12-03_cpu/session39/sharp)."""
    road = torch.full((len(masks),), math.nan)
    if len(rows):
        road[rows] = road_axes(image, intrinsics.matrix(), masks[rows], masks.any(0))
    return road


def _with_road(records: list[ProposalFit], ids: Tensor, road: Tensor) -> list[ProposalFit]:
    """``records`` with the road's axis each fit was drawn towards (degrees; the rows of ``road (N,)`` by ``ids``);
    a record of a row without one (NaN) keeps its own."""
    at = {int(i): float(r) for i, r in zip(ids.tolist(), road.tolist(), strict=True) if math.isfinite(r)}
    return [replace(r, road_axis_deg=math.degrees(at[r.instance_id])) if r.instance_id in at else r for r in records]


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
              annotated: Tensor | None = None, photo: InputPhoto | None = None, tail: Tensor | None = None
              ) -> tuple[tuple[Tensor, ...], Appearance | None]:
    """``(geometry, appearance)``: geometry ``template (N,), dims (N, 3), ry (N,), location (N, 3), phi (N, 64, 3)``
    of the objects ``masks`` (template -1 and placeholders for objects without a usable prediction); ``gt``:
    annotated boxes, looked up for the rows ``annotated (N,)`` bool (None: all). ``appearance``: what the branch saw
    of each object (:class:`~sdn3d.geometric.facing.Appearance`: its yaw before the lamp cue, the lamps' reading,
    a MultiBin net's bins; the box fit's yaw belief), None without a lamp cue. ``photo``: the crops' source
    (:func:`_predict_geometry`)."""
    n = len(ids)
    template = torch.full((n,), -1, dtype=torch.long)
    dims, location = torch.ones(n, 3, dtype=torch.float64), torch.zeros(n, 3, dtype=torch.float64)
    location[:, 2] = 1.0
    ry, phi = torch.zeros(n, dtype=torch.float64), torch.zeros(n, 64, 3)
    rows = (masks.flatten(1).sum(1) >= min_pixels).nonzero().flatten()
    if models.geometric is None or not len(rows):
        return (template, dims, ry, location, phi), None
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
        return (template, dims, ry, location, phi), None
    pred = {k: v.detach().cpu() for k, v in _predict_geometry(image, intr, masks[rows], boxes, models, refine, photo,
                                                                      None if tail is None else tail[rows]).items()}
    ok = (torch.isfinite(pred["dims"]).all(1) & torch.isfinite(pred["location"]).all(1) & torch.isfinite(pred["ry"])
          & torch.isfinite(pred["phi"]).flatten(1).all(1) & (pred["dims"] > 0).all(1) & (pred["center"][:, 2] > 0))
    if not bool(ok.all()):
        log.warning("derender: %d object(s) got no usable 3D prediction and keep their 2D mask", int((~ok).sum()))
    keep = rows[ok]
    template[keep] = pred["template_id"][ok].long()
    dims[keep], location[keep] = pred["dims"][ok].double(), pred["location"][ok].double()
    ry[keep], phi[keep] = pred["ry"][ok].double(), pred["phi"][ok].float()
    return (template, dims, ry, location, phi), _appearance(pred, rows, ok, n, models)


def _appearance(pred: dict[str, Tensor], rows: Tensor, ok: Tensor, n: int, models: Models) -> Appearance | None:
    """The :class:`~sdn3d.geometric.facing.Appearance` of the ``n`` objects from the predictions ``pred`` of the
    rows ``rows`` (usable where ``ok``); None where the predictor read no lamps."""
    from sdn3d.geometric.facing import APPEARANCE_KEYS, BIN_KEYS, BORDER_KEYS, FRONT_KEYS, Appearance

    if models.geometric.lamp_cue is None or any(k not in pred for k in APPEARANCE_KEYS):
        return None
    values = {}
    for k in APPEARANCE_KEYS + tuple(k for k in BIN_KEYS + FRONT_KEYS + BORDER_KEYS if k in pred):
        value = torch.zeros((n, *pred[k].shape[1:]), dtype=pred[k].dtype)
        value[rows[ok]] = pred[k][ok]
        values[k] = value
    has = torch.zeros(n, dtype=torch.bool)
    has[rows[ok]] = True
    return Appearance(values, has, models.geometric.lamp_cue)


def _checked_image(image: Tensor, intrinsics: Intrinsics, gt: GroundTruth | None) -> Tensor:
    """``image`` as float32 on the CPU, clamped to ``[0, 1]``, after checking it and its companions."""
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


def _semantics_and_instances(image: Tensor, models: Models, proposals: Proposals, gt: GroundTruth | None,
                             name: str) -> tuple[Tensor, Tensor, str, str, Segmentation | None]:
    """Steps 1-2 of the module doc: ``(semantic (H, W), instances (H, W), proposal source, semantic source,
    segmentation)`` with the sources :func:`~sdn3d.proposals.choose_sources` chose: ``'gt'`` (the oracle),
    ``'semantic'`` / ``'branch'`` (the semantic branch), ``'boxes'`` (no proposal but the boxes) and ``'none'`` (no
    semantics: every pixel 255, ignore); ``segmentation``: the branch's output where it ran, else None."""
    height, width = image.shape[-2:]
    sources = choose_sources(proposals, models.semantic is not None, gt is not None,
                             gt is not None and gt.instances is not None, gt.key if gt is not None else "")
    seg = None
    if sources.runs_branch:
        _check_class_count(models, CLASS_LISTS[name], name)
        seg = models.semantic(image)
    semantic = (seg.label[0].cpu() if sources.semantics == "branch" else gt.semantic if sources.semantics == "gt"
                else torch.full((height, width), 255, dtype=torch.long))
    instances = (gt.instances if sources.masks == "gt" else seg.instance[0].cpu() if sources.masks == "semantic"
                 else torch.zeros(height, width, dtype=torch.long))
    return semantic, instances, sources.masks, sources.semantics, seg


def _check_class_count(models: Models, class_list: tuple, name: str) -> None:
    if len(models.semantic.classes) != len(class_list):
        raise UserInputError(f"the semantic model predicts {len(models.semantic.classes)} classes, the scene's "
                             f"class list {name!r} has {len(class_list)}")


def derender(image: Tensor, intrinsics: Intrinsics, models: Models, proposals: Proposals | str = Proposals.AUTO,
             ground_truth: GroundTruth | None = None, *, classes: str | None = None, min_pixels: int = 64,
             refine: RefineSettings | None = None, boxes: BoxPrompts | None = None,
             fit: FitSettings | None = None, photo: InputPhoto | None = None) -> SceneCode:
    """De-render ``image (3, H, W)`` float in ``[0, 1]`` into a scene (module doc).

    Args:
        image: the image at the working size; ``intrinsics`` must be of that size.
        models: the branches (None ones are skipped; see ``proposals``).
        proposals: a :class:`~sdn3d.proposals.Proposals` (or its value): ``'auto'``: semantic map from the semantic
            branch (the ground truth's without one), masks from the ground-truth instance map if there is one, else
            the branch's instance head; ``'gt'``: semantic map and masks from ``ground_truth`` (an oracle);
            ``'semantic'``: both from the semantic branch; ``'boxes'``: the objects are ``boxes`` alone (semantics
            from the branch, else the ground truth, else none: 255).
        ground_truth: the frame's ground truth at the working size (oracle maps and annotated boxes),
            optional; :func:`sdn3d.data.scene_gt.ground_truth` builds it from a dataset frame.
        classes: class list name (default: from the ground truth or the models).
        min_pixels: visible pixels (at the working size) an object needs to get 3D geometry.
        refine: optional reprojection refinement of the geometric predictions (Cityscapes setting).
        boxes: objects named by a box, added to (or, ``'boxes'``, instead of) the proposals.
        fit: the test-time fit of the proposals' vehicles (:func:`sdn3d.proposal_fit.fit_proposals`, each started
            from its prediction; ``meta['fits']`` holds each one's :class:`~sdn3d.proposal_fit.ProposalFit`); None:
            the branch's predictions as they are (the paper's protocol). Box objects are always fitted.
        photo: the photo ``image`` was made from, at its own resolution (:class:`~sdn3d.image_ops.InputPhoto`;
            :meth:`sdn3d.editing.frame.PixelFrame.photo`): the geometric branch's crops are read from it (module
            doc, step 3); None: from ``image``. Everything else works at the working size.

    Raises:
        ValueError: bad image / intrinsics or an unknown ``proposals`` (the caller's mistake).
        UserInputError (a ValueError): no source for the semantic map or the proposals, a semantic
            model of another class list (the user's settings or checkpoints), or ``'boxes'`` without boxes.
    """
    gt = ground_truth
    proposals = Proposals.parse(proposals)
    image = _checked_image(image, intrinsics, gt)
    if proposals is Proposals.BOXES and (boxes is None or not len(boxes)):
        raise UserInputError("proposals='boxes' needs objects given by a box (an edit spec's `objects:`)")
    name = _class_list_name(models, gt, classes)
    class_list = CLASS_LISTS[name]
    with ThreadPoolExecutor(1) as pool:  # GrabCut without a prior needs no semantics: it runs beside the branch
        early = pool.submit(box_grabcut, image, boxes)  # (OpenCV and torch's operations release the GIL)
        semantic, instances, source, semantic_source, seg = _semantics_and_instances(image, models, proposals, gt,
                                                                                     name)
        found = early.result()

    # Proposals: ids of instance classes only (a scene's objects must be things).
    things = torch.tensor([c.id for c in class_list if c.has_instances], dtype=torch.long)
    ids = instances.unique()
    ids = ids[(ids >= INSTANCE_DIVISOR) & torch.isin(ids // INSTANCE_DIVISOR, things)]
    masks = instances[None] == ids[:, None, None]  # (N, H, W)
    box_rows, box_fits, mask_source = torch.zeros(0, dtype=torch.long), [], None
    if boxes is not None and len(boxes):
        masks, ids, box_rows, mask_source = add_box_objects(image, masks, ids, boxes, seg, things, class_list, found)
    class_names = {c.id: c.name for c in class_list}
    unsure_pixels = None  # the pixels the semantic branch is unsure are a vehicle's (FitSettings.unsure_vehicle)
    if source == "semantic" and seg is not None and fit is not None and fit.unsure_vehicle is not None:
        vehicle = seg.probability[0, things].sum(0).float().cpu()
        unsure_pixels = (vehicle > 0.5 - fit.unsure_vehicle) & (vehicle < 0.5 + fit.unsure_vehicle)
    stage = (image, intrinsics, source, gt, models, min_pixels, refine, photo, boxes, fit, class_names, unsure_pixels)
    objects = _objects_3d(masks, ids, box_rows, *stage)
    groups = (footprint_joins(masks, ids, objects.geometry, objects.fits, fit.join_overlap)
              if fit is not None and fit.join_overlap is not None and source == "semantic" else [])
    if groups:  # one car cut in parts (proposal_fit's module doc): joined, and de-rendered again where that changed
        joined = {int(ids[g[0]]): tuple(ids[g].tolist()) for g in groups}
        members = torch.cat([g[1:] for g in groups])
        for g in groups:
            instances = torch.where(torch.isin(instances, ids[g]), ids[g[0]], instances)
        first = objects.with_ignore(masks, fit)  # what each fit read of the others, on the masks before the join
        masks, ids, kept = join_masks(masks, ids, groups)
        box_rows = box_rows - (members[:, None] < box_rows[None]).sum(0)  # the rows dropped before each box's
        same = ~torch.isin(ids, torch.tensor(list(joined), dtype=torch.long))  # the masks the join left as they were
        objects = _objects_3d(masks, ids, box_rows, *stage, earlier=first.rows(kept), same=same)
        objects = replace(objects, fits=[replace(r, joined_from=joined.get(r.instance_id, ())) for r in objects.fits])
        log.info("derender: %d proposal(s) joined into %d (their fitted cars shared the ground)",
                 len(members) + len(groups), len(groups))
    geometry, appearance, proposal_fits, box_result = (objects.geometry, objects.appearance, objects.fits,
                                                       objects.box_result)
    n = len(ids)
    classes = [class_names.get(int(i) // INSTANCE_DIVISOR) for i in ids]  # each object's: it bounds its templates
    if len(box_rows):
        masks, geometry, box_fits, vacated = fit_box_objects(image, intrinsics, masks, ids, box_rows, boxes, geometry,
                                                             min_pixels, mask_source, appearance, box_result, classes,
                                                             objects.box_axes)
        if vacated is not None:
            instances = torch.where(vacated, torch.zeros_like(instances), instances)
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
            "objects": n, "with_geometry": int(geo.sum()), "crop_size": models.crop_size, "min_pixels": min_pixels,
            "crops_from": "image" if photo is None else "photo"}
    if fit is not None:
        meta["proposal_fit"] = fit.to_dict()
        meta["fits"] = [r.to_json() for r in proposal_fits]
    if box_fits:
        meta["boxes"] = box_fits
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
