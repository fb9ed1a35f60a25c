"""The test-time fit of the proposals' vehicles: every object the edit path de-renders gets the box objects' fit.

:func:`sdn3d.derender.derender` gives each proposal (the semantic branch's masks, or the ground truth's: an oracle)
the geometric branch's prediction. At a short training budget that prediction lists most cars as one template, a
few per cent too far and now and then end for end (issue 40); the box objects' test-time fit
(:func:`sdn3d.geometric.fit.fit_to_masks`: every template and four yaws on the road plane, the prediction and its
flip as two more hypotheses) chose the right template for 47 % of held-out cars against the branch's 15 %, and
halved the distance error. :func:`fit_proposals` runs the same fit for the proposals' vehicles, started from their
predictions, each with the pixels of the objects in front of it ignored (nearer by the prediction's depth; objects
without geometry count as in front, their depth unknown). :class:`ProposalFit` is each object's record.

A semantic branch's mask often stops short of the car's bottom: the dark rows of tyres and shadow are labelled
road (issue 40; on tuning seeds 31 and 35, 27 of 208 fitted proposals ended 2-9 px above the car's, and the fit,
whose road plane reads the distance off the bottom edge, put those cars a median 56-82 % too far). For such
proposals (``unsure`` of :func:`fit_proposals`: the caller's choice, :func:`unsure_below` for the semantic branch's
masks) a band under each mask, as deep as :data:`UNSURE_BELOW` of the mask's height, counts as neither car nor
background, like an occluder's pixels: the car's width and top then place it, and its bottom may reach the road.

The semantic branch also cuts a near car into two or more proposals (issues 40 and 41: on the seven Table 1 tuning
trees, session 21's demo weights, 58 fragments on 52 cars, most from two centre-heatmap peaks on one car), and each
part is fitted as a whole car, then turned, moved or deleted alone. Nothing the grouping sees in 2D tells such a cut
from two touching cars (``docs/results/2026-11-30_cpu/session26/frag40`` and ``split40``); the fit does: two real
cars cannot stand on the same ground, while the parts of one car, each fitted as a whole car, often do.
:func:`footprint_joins` finds the proposals whose masks touch and whose fitted footprints on the road share at least
``FitSettings.join_overlap`` of the smaller one (a car partly hidden behind another is fitted behind it: their
footprints share little); the de-render then joins each group's masks into one proposal and fits it once more
(``docs/results/2026-11-30_cpu/session27/join40``), with the other proposals whose fit reads something the join
changed (:func:`proposal_ignore`: a fit reads the other objects only as the pixels it is fitted without, in its
windows; ``docs/results/2026-12-01_cpu/session29/joincost29``).

The paper fits nothing at test time on Virtual KITTI (its Table 1 and 2 protocol): ``fit=None`` in
:func:`~sdn3d.derender.derender` keeps that.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import torch
from torch import Tensor

from sdn3d.box_objects import occluder_masks, yaw_belief
from sdn3d.image_ops import mask_boxes
from sdn3d.labels import INSTANCE_DIVISOR, VEHICLE_CLASS_NAMES
from sdn3d.math3d.camera import Intrinsics
from sdn3d.math3d.transforms import convex_overlap, ground_footprints

if TYPE_CHECKING:
    from sdn3d.geometric.facing import Appearance
    from sdn3d.geometric.fit import FitRequest, FitResult, FitSettings

__all__ = ["ProposalFit", "fit_proposals", "fit_proposals_and_boxes", "choose_proposals_again", "proposal_request",
           "proposal_ignore", "apply_proposal_fit", "vehicle_rows", "unsure_below",
           "footprint_joins", "join_masks", "UNSURE_BELOW"]

#: Depth of the band under a predicted mask that the fit ignores (:func:`unsure_below`), as a fraction of the mask's
#: height: the semantic branch's masks miss up to a quarter of a far car's rows (module doc).
UNSURE_BELOW = 0.3


@dataclass(frozen=True)
class ProposalFit:
    """One proposal's test-time fit: its silhouette IoU with its mask (None: not fitted, the prediction kept), whether
    that is poor (under ``FitSettings.poor_iou``), the winning hypothesis in words, the fit's note, if any, and the
    ids of the proposals it was joined from (:func:`footprint_joins`; its own id first; empty: not joined), and the
    road's axis the fit was drawn towards (a yaw in degrees, :func:`~sdn3d.road_heading.road_axes`; None: none)."""

    instance_id: int
    iou: float | None
    poor: bool
    hypothesis: str | None
    note: str | None = None
    joined_from: tuple[int, ...] = ()
    road_axis_deg: float | None = None

    def to_json(self) -> dict:
        return {"id": self.instance_id, "fit_iou": None if self.iou is None else round(self.iou, 4),
                "poor_fit": self.poor, "hypothesis": self.hypothesis, "note": self.note,
                "joined_from": list(self.joined_from),
                "road_axis_deg": None if self.road_axis_deg is None else round(self.road_axis_deg, 2)}


def vehicle_rows(ids: Tensor, template: Tensor, class_names: dict[int, str]) -> Tensor:
    """``(K,)`` rows of the objects ``ids (N,)`` with a prediction (``template >= 0``) whose class is a vehicle."""
    vehicle = torch.tensor([class_names.get(int(i) // INSTANCE_DIVISOR, "").lower() in VEHICLE_CLASS_NAMES
                            for i in ids.tolist()], dtype=torch.bool)
    return (vehicle & (template >= 0)).nonzero().flatten()


def unsure_below(masks: Tensor, fraction: float | None = None) -> Tensor:
    """``(N, H, W)`` bool: under each of the ``masks (N, H, W)``, in each of its columns, the pixels from its lowest
    one down to ``ceil(fraction * height)`` rows below the mask's bottom edge (``height``: its box's rows; None:
    :data:`UNSURE_BELOW`), where no mask is: where a mask that may have missed the car's bottom rows (module doc)
    could still be the car.

    >>> m = torch.zeros(1, 8, 3, dtype=torch.bool); m[0, 1:4, :2] = True; m[0, 1:5, 2] = True
    >>> unsure_below(m, 0.5)[0].int().tolist()  # rows 1-4: down to row 6, each column from its own lowest pixel
    [[0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0], [1, 1, 0], [1, 1, 1], [1, 1, 1], [0, 0, 0]]
    """
    fraction = UNSURE_BELOW if fraction is None else fraction
    n, h, _ = masks.shape
    if n == 0 or fraction <= 0:
        return torch.zeros_like(masks, dtype=torch.bool)
    y = torch.arange(h)
    rows = masks.any(2)  # (N, H)
    top = torch.where(rows, y, h).amin(1)
    bottom = torch.where(rows, y, -1).amax(1)
    last = bottom + torch.ceil(fraction * (bottom - top + 1).clamp_min(0)).long()  # (N,) the band's lowest row
    under = masks.long().cumsum(1) > 0  # at or below a mask pixel of the same column
    band = under & ~masks & (y[None, :, None] <= last[:, None, None])
    return band & ~masks.any(0)


def footprint_joins(masks: Tensor, ids: Tensor, geometry: tuple[Tensor, ...], records: Sequence[ProposalFit],
                    overlap: float) -> list[Tensor]:
    """The groups of fitted proposals that are one car (module doc): ``(M,)`` rows of ``ids (N,)`` each (``M >= 2``,
    the largest mask first, then by row), taken transitively over the pairs of proposals fitted by the fit of
    ``records`` (:func:`fit_proposals`' records; one with ``iou`` None, left alone by the fit, joins nothing) whose
    ``masks (N, H, W)`` touch (8-neighbours) and whose fitted footprints (``geometry``'s ``dims, ry, location``:
    :func:`~sdn3d.math3d.transforms.ground_footprints`) share at least ``overlap`` of the smaller footprint's area."""
    row_of = {int(i): k for k, i in enumerate(ids.tolist())}
    rows = torch.tensor(sorted(row_of[r.instance_id] for r in records if r.iou is not None), dtype=torch.long)
    if len(rows) < 2:
        return []
    m = masks[rows]
    grown = torch.nn.functional.max_pool2d(m[:, None].float(), 3, 1, 1)[:, 0]  # (K, H, W): each mask and its ring
    touch = (grown.flatten(1) @ m.flatten(1).float().T > 0).triu(1)  # (K, K) pairs a < b
    _, dims, ry, location, _ = geometry
    feet = ground_footprints(dims[rows], ry[rows], location[rows])  # (K, 4, 2)
    area = dims[rows, 0].double() * dims[rows, 2].double()
    group = list(range(len(rows)))  # union-find over the joined pairs

    def root(k: int) -> int:
        while group[k] != k:
            k = group[k]
        return k

    for a, b in touch.nonzero().tolist():  # a few touching pairs per image
        if convex_overlap(feet[a], feet[b]) >= overlap * float(torch.minimum(area[a], area[b])):
            group[root(b)] = root(a)
    members: dict[int, list[int]] = {}
    for k in range(len(rows)):
        members.setdefault(root(k), []).append(k)
    pixels = m.flatten(1).sum(1)
    return [rows[sorted(ks, key=lambda k: (-int(pixels[k]), k))] for ks in members.values() if len(ks) > 1]


def join_masks(masks: Tensor, ids: Tensor, groups: Sequence[Tensor]) -> tuple[Tensor, Tensor, Tensor]:
    """``(masks (N', H, W), ids (N',), kept (N,) bool)``: each of the ``groups`` (:func:`footprint_joins`' rows of
    ``masks (N, H, W)``) made one object, the union of its masks under its first row's id; the other rows dropped
    (``kept`` False)."""
    masks, kept = masks.clone(), torch.ones(len(ids), dtype=torch.bool)
    for g in groups:
        masks[g[0]] = masks[g].any(0)
        kept[g[1:]] = False
    return masks[kept], ids[kept], kept


def fit_proposals(intr: Intrinsics, masks: Tensor, ids: Tensor, rows: Tensor, geometry: tuple[Tensor, ...],
                  settings: FitSettings, appearance: Appearance | None = None, unsure: Tensor | None = None,
                  classes: Sequence[str | None] | None = None, unsure_pixels: Tensor | None = None,
                  road: Tensor | None = None, lane_reg: float | None = None
                  ) -> tuple[tuple[Tensor, ...], list[ProposalFit], FitResult | None]:
    """``(geometry, records, fit)``: the rows ``rows (K,)`` of ``geometry`` (``template (N,), dims (N, 3), ry (N,),
    location (N, 3), phi (N, 64, 3)``, the branch's predictions) fitted to their ``masks (N, H, W)`` (module doc),
    and the fit's result for those rows (None without rows; its ``choice``: :func:`choose_proposals_again`).

    Rows whose mask is too small or thin to fit keep their prediction (a record with ``iou`` None and the fit's
    note). Objects outside ``rows`` are untouched; they still hide the fitted ones where they are nearer.
    ``appearance``: what the geometric branch saw of each object, the fit's yaw belief with ``settings.appearance``
    (as for the box objects: :func:`~sdn3d.box_objects.yaw_belief`). ``unsure``: ``(N, H, W)`` bool pixels that
    count for no object (:func:`unsure_below`; None: none). ``classes``: the class name of every object (the
    templates each may be drawn with, :func:`~sdn3d.geometric.fit.allowed_templates`; None: any).
    ``unsure_pixels``: ``(H, W)`` bool pixels every object's silhouette loss leaves out, its mask keeping them
    (:attr:`~sdn3d.geometric.fit.FitSettings.unsure_vehicle`; None: none). ``road``: ``(N,)`` the road's axis where
    each object stands (:func:`~sdn3d.road_heading.road_axes`, NaN: unknown); None: none. ``lane_reg``: the lane
    prior's weight for these rows (:attr:`~sdn3d.geometric.fit.FitSettings.proposal_lane_reg` for the semantic
    branch's proposals); None: the settings' ``lane_reg``. :func:`proposal_request` and
    :func:`apply_proposal_fit` are its two halves, for a caller that fits these objects with others
    (:func:`~sdn3d.geometric.fit.fit_many`).
    """
    from sdn3d.geometric.fit import fit_many

    if not len(rows):
        return tuple(g.clone() for g in geometry), [], None
    request = proposal_request(masks, rows, geometry, settings, appearance, unsure, classes, unsure_pixels, road,
                               lane_reg)
    result = fit_many([request], intr, settings=settings)[0]
    return (*apply_proposal_fit(result, ids, rows, geometry, settings), result)


def fit_proposals_and_boxes(intr: Intrinsics, masks: Tensor, ids: Tensor, rows: Tensor,
                            geometry: tuple[Tensor, ...], settings: FitSettings, appearance: Appearance | None,
                            boxes: FitRequest, unsure: Tensor | None = None,
                            classes: Sequence[str | None] | None = None, unsure_pixels: Tensor | None = None,
                            road: Tensor | None = None, lane_reg: float | None = None
                            ) -> tuple[tuple[Tensor, ...], list[ProposalFit], FitResult | None, FitResult]:
    """:func:`fit_proposals` and the fit of the box objects' request ``boxes``
    (:func:`~sdn3d.box_objects.box_request`, the same ``settings``) in one :func:`~sdn3d.geometric.fit.fit_many`
    call: each stage's fixed cost once. Neither reads the other's fit, so the fits are those of two calls (up to the
    order of float sums). Returns ``(geometry, records, the proposals' FitResult, the boxes' FitResult)``."""
    from sdn3d.geometric.fit import fit_many

    if not len(rows):
        return (*fit_proposals(intr, masks, ids, rows, geometry, settings, appearance, unsure, classes,
                               unsure_pixels, road, lane_reg), fit_many([boxes], intr, settings=settings)[0])
    request = proposal_request(masks, rows, geometry, settings, appearance, unsure, classes, unsure_pixels, road,
                               lane_reg)
    fits = fit_many([request, boxes], intr, settings=settings)
    return (*apply_proposal_fit(fits[0], ids, rows, geometry, settings), fits[0], fits[1])


def choose_proposals_again(fit: FitResult, ids: Tensor, rows: Tensor, again: Tensor, geometry: tuple[Tensor, ...],
                           settings: FitSettings, appearance: Appearance | None
                           ) -> tuple[tuple[Tensor, ...], list[ProposalFit]]:
    """``(geometry, records)``: ``geometry`` with the proposals ``again (M,)`` (a subset of the fitted ``rows (K,)``
    of ``fit``, :func:`fit_proposals`' result) chosen again among the fits of the first fit's fine stage under the
    yaw belief of ``appearance`` (a lamp reading that changed: :func:`sdn3d.derender.derender`), and their records:
    what fitting them again with that appearance gives (the hypotheses and their fits do not read the belief,
    :class:`~sdn3d.geometric.fit.FitChoice`), without the fitting."""
    from sdn3d.geometric.fit import choose_again

    if fit.choice is None:
        raise ValueError("choose_proposals_again needs the fit's choice (a FitResult of fit_to_masks)")
    position = {int(r): k for k, r in enumerate(rows.tolist())}
    at = torch.tensor([position[int(r)] for r in again.tolist()], dtype=torch.long)
    result = choose_again(fit.choice.rows(at), yaw_belief(appearance if settings.appearance else None, again))
    return apply_proposal_fit(result, ids, again, geometry, settings)


def proposal_request(masks: Tensor, rows: Tensor, geometry: tuple[Tensor, ...], settings: FitSettings,
                     appearance: Appearance | None = None, unsure: Tensor | None = None,
                     classes: Sequence[str | None] | None = None, unsure_pixels: Tensor | None = None,
                     road: Tensor | None = None, lane_reg: float | None = None) -> FitRequest:
    """What :func:`fit_proposals` asks the fit for the rows ``rows (K,)`` (non-empty): their masks, boxes, the pixels
    of nearer objects and the ``unsure`` ones (``(N, H, W)`` or None), the ``unsure_pixels (H, W)`` their
    silhouette loss leaves out (or None), the predictions as starts, the yaw belief and the road's axes (``road
    (N,)`` or None) and their weight ``lane_reg`` (None: the settings') (``classes``: the class name of every object,
    None: unknown)."""
    from sdn3d.geometric.fit import FitRequest

    template, dims, ry, location, _ = geometry
    return FitRequest(masks[rows], mask_boxes(masks[rows]).float(),
                      ignore=proposal_ignore(masks, geometry, unsure)[rows], start_ry=ry[rows].float(),
                      start_dims=dims[rows].float(), start_template=template[rows],
                      start_location=location[rows].float(),
                      yaw_belief=yaw_belief(appearance if settings.appearance else None, rows),
                      classes=None if classes is None else [classes[int(r)] for r in rows],
                      unsure_pixels=None if unsure_pixels is None else unsure_pixels[None].expand(len(rows), -1, -1),
                      road_ry=None if road is None else road[rows].float(), lane_reg=lane_reg)


def proposal_ignore(masks: Tensor, geometry: tuple[Tensor, ...], unsure: Tensor | None = None,
                    settings: FitSettings | None = None) -> Tensor:
    """``(N, H, W)`` bool: the pixels each of the objects ``masks (N, H, W)`` is fitted without
    (:func:`proposal_request`): the masks of the objects nearer than it by ``geometry``'s prediction (``template (N,),
    dims, ry, location (N, 3), phi``; an object without one counts as in front of everything: its pixels may hide) and
    its ``unsure`` band (``(N, H, W)``, :func:`unsure_below`; None: none). With ``settings``: only those its fit reads
    (:func:`~sdn3d.geometric.fit.read_pixels`), all that its fit reads of the other objects
    (:func:`sdn3d.derender.derender` fits again after a join only the objects where that changed)."""
    template, _, _, location, _ = geometry
    depth = torch.where(template >= 0, location.norm(dim=1).float(), torch.zeros(len(template)))
    ignore = occluder_masks(masks, depth)
    if unsure is not None:
        ignore = ignore | unsure
    if settings is None:
        return ignore
    from sdn3d.geometric.fit import read_pixels

    return ignore & read_pixels(mask_boxes(masks).float(), tuple(masks.shape[1:]), settings)


def apply_proposal_fit(result: FitResult, ids: Tensor, rows: Tensor, geometry: tuple[Tensor, ...],
                       settings: FitSettings) -> tuple[tuple[Tensor, ...], list[ProposalFit]]:
    """:func:`fit_proposals`' output from the fit ``result`` of :func:`proposal_request`'s rows ``rows``."""
    template, dims, ry, location, phi = (g.clone() for g in geometry)
    fitted = result.fitted if len(result.fitted) else torch.ones(len(rows), dtype=torch.bool)
    take = rows[fitted]
    template[take] = result.template[fitted]
    dims[take], ry[take] = result.dims[fitted].double(), result.ry[fitted].double()
    location[take], phi[take] = result.location[fitted].double(), result.phi[fitted].float()
    records = []
    for k, iid in enumerate(ids[rows].tolist()):
        iou = float(result.iou[k]) if bool(fitted[k]) else None
        records.append(ProposalFit(int(iid), iou, iou is None or iou < settings.poor_iou,
                                   result.hypothesis_name(k), result.notes.get(k)))
    return (template, dims, ry, location, phi), records
