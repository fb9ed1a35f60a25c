"""Fit a vehicle's 3D shape and pose to its silhouette alone: objects a person named by a box (real photos).

The paper fits its Virtual-KITTI-trained predictions to Cityscapes cars by minimising the reprojection loss for 16
Adam steps (:mod:`sdn3d.geometric.refine`). A car in a photo the branches never saw needs more than a local polish,
so :func:`fit_to_masks` searches, batched over all objects and hypotheses at once:

1. **On the road.** The camera has no roll or pitch and the road is the plane ``y = camera_height`` of the
   camera frame, so the car's bottom-face centre is ``(x, camera_height, z)``: two free numbers,
   started where the ray through the middle of the box's bottom edge meets the road (pushed back by half a car
   width, the box's bottom edge is the car's nearest side). The camera's height over the road is
   ``camera_height``, by default KITTI's 1.65 m (a given camera's own height wins: ``sdn3d-edit``'s
   ``input.camera``). With ``camera_height=None`` it is measured in the image (issue 40): the median height of the
   predicted cars' bottom faces (the geometric branch's ``start_location``, from each car's box, distance and
   projected centre), within ``camera_height_range``; without a prediction it is ``default_camera_height``. The
   synthetic cameras sit 1.50-1.65 m up, so 1.65 m places their cars up to about 8 % too far and too large; the
   measured height was worse still at the demo's budget, whose predicted distances are about 12 % off
   (docs/results/2026-11-28_cpu/issue40_poses/), so it is not the default.
2. **Many starts, then the best.** Every template of the bank that the object's class allows (``classes``,
   :func:`allowed_templates`: a car is no minibus or bus, a van is the one-box van, the minibus or the bus: a
   silhouette alone let vans be fitted as cars and cars as minibuses, docs/results/2026-11-29_cpu/session11/template/)
   times four starting yaws (the geometric branch's
   prediction where there is one, else facing away from the camera; its reverse; the two sides) is fitted at a
   coarse crop (``coarse_size`` px, ``coarse_steps`` Adam steps on x, log z, yaw and log dims), each template cut to
   ``coarse_faces`` faces (an outline 32 px across needs no more). The ``keep`` best
   hypotheses of each object, and the prediction itself (its template where the class allows it, else the best
   start's; its place on the road, yaw and size), go on at
   a finer crop with the free-form deformation (``fine_steps``); the one with
   the lowest loss wins, so the template is chosen by its fit. A silhouette barely tells a car's front from its
   back: the prediction's end-for-end flip is always one more fine hypothesis, and among the fits within ``tie``
   (a share) of the best loss the appearance decides: the one whose yaw the branch believes most (``yaw_belief``,
   e.g. a MultiBin branch's bin confidences, :func:`sdn3d.geometric.model.yaw_distribution`), else the one whose
   yaw is nearest the first start (the prediction's: a MultiBin branch's front/back). Before that, the appearance
   decides the end (``facing_tie``): a fit drops out where another one on its axis facing the other end
   (:data:`FACING_AXIS`) is believed clearly more (by :data:`FACING_MARGIN`) and its loss is within ``facing_tie``
   of the fit's; a silhouette that prefers an end more clearly than that keeps it, and the axis stays the
   silhouette's. With an appearance belief, the prediction mirrored about the line of sight (``mirror``:
   ``alpha -> pi - alpha``, the same end seen, its front to the other side) and that mirror's flip are two more
   fine hypotheses. :attr:`FitResult.hypothesis` records the winner (0: the prediction, 1: its flip, 2: its
   mirror, 3: the mirror's flip, 4..: the search's best starts; without the mirror, the search's are 4.. too).
   **A car the image's left or right border cuts** (:func:`~sdn3d.geometric.lamps.border_side` of its box) lies
   beside the camera, and the end facing the camera (the near end, towards ``sign(sin(alpha)) cos(alpha)`` across
   the image, ``alpha = ry - ray``) lies at that border: a fit whose near end points inwards is a view whose near
   end would be inside the picture, which the border contradicts. It is the silhouette's depth reflection
   (``alpha -> -alpha``, which an outline hardly tells apart), and on cut cars the fit often preferred it. So such
   fits drop out before the choice (``cut_inward``: where ``side * sin(2 alpha) < -cut_inward``, ``side`` +1 for
   the right border, -1 for the left, each fit's ``ray`` through its own place), unless every fit of the car would,
   or unless the winner left is believed less by the appearance (``yaw_belief``) than the inward fit it displaces:
   the border tells the near end's side, not which end is near, and the fits left often held the right axis with
   only its wrong end (on the Table 1 tuning trees, dropping without this turned 6 more fits end for end).
   ``sin(2 alpha)`` is the near end's direction weighed by how far the car is turned from an end or side view,
   where the near end's side is moot: it is continuous where ``sign(sin(alpha))`` is not.
3. **What counts.** The loss is L_reproj (mean ``|S~ - M|``) over the crop, without the pixels of nearer objects
   (``ignore``) and outside the image, plus ``dims_reg * |log d - log d0|^2`` (keeps the size near the start
   where the silhouette cannot tell: a car seen from behind has no visible length, and a box-like car turned by 90
   degrees with its length and width swapped casts nearly the same silhouette; with ``dims_reg = 0.1`` such a swap
   costs about 0.16, more than a whole silhouette's L1 error), ``yaw_reg * (1 - cos(ry - ry0)) / 2`` (a pull towards
   the first start's yaw, the prediction's: where the silhouette cannot tell front from back or a turn of 90
   degrees, the prediction does; a wrong prediction loses to a silhouette that disagrees clearly),
   ``template_size_reg * |log d - log d_t|^2`` (the size near the typical size ``d_t`` of the template drawn: the
   template a silhouette cannot tell is told by the size), ``ffd_reg * mean(phi^2)`` and, where the caller gives the
   road's axis at the object (``road_ry``: :func:`sdn3d.derender.derender` does for every object it fits),
   ``lane_reg *`` :func:`lane_prior` (0 on the axis at either end, about 1 beyond twice ``lane_width_deg``): a
   proposal's rounded outline fits many yaws about equally well, a car seen end-on casts nearly the same outline at
   any yaw near its true one, and nearly every car stands along its lane. The semantic branch's proposals are pulled
   harder (``proposal_lane_reg``) than the sharp outlines of box objects and of the ground truth's masks, which can
   show a car parked askew.

The fit's quality is the silhouette IoU of the winner with the mask at the fine crop (the soft silhouette
thresholded at 0.5, ignored pixels left out): :attr:`FitResult.iou`. A mask too small or too thin to fit
(``min_mask_pixels``, ``min_mask_side``) keeps the branch's prediction where there is one (``FitResult.fitted``
False, a warning naming the object in ``FitResult.warnings``), never a silent flip. Shapes in the docstrings:
``N`` objects, ``T`` templates, ``Y`` starting yaws.

**Cost** (issue 40: 10 objects at 624x192 within 3 s). Nearly all of it is the soft silhouettes' (face, pixel)
pairs, Adam step after Adam step. The search stops the starts that lag: after a third of its steps only the
``coarse_survivors`` best of each object go on; it draws templates cut to ``coarse_faces`` faces, and the fine stage
fits them cut to ``fine_faces`` at ``fine_size`` px (the winner's IoU is measured with its full mesh). The step
counts stay: fewer steps cost template accuracy and silhouette IoU on the seed-13 tuning tree (10 fine and 8 search
steps: template -8 pp, 95 % interval [-15.7, -0.4]). :func:`fit_many` fits several callers' objects in one call
(:func:`sdn3d.derender.derender`'s proposals and box objects): each stage's fixed cost once. The stages run on one
torch thread whatever the caller's count (more threads cost CPU time and win nothing on such small operations); the
objects are fitted in up to ``parts`` groups instead, one per torch thread the caller has, each on its own Python
thread (the operations release the GIL), and the soft raster's kernel splits its meshes over the caller's threads
where one group runs alone. So the fit is the same at any thread count of at least ``parts``, and on one thread it is
the fit of one group (the two differ by the order of float operations only). With ``cull_backfaces`` (off by default)
the Adam steps draw only the faces facing the camera (a third less time), the losses that rank hypotheses every face.
The FFD moves by ``ffd_step`` (0.1) of the Adam step: with the full step the fine stage's mean loss jumped from 0.14 to
0.42 at its first step and swung for the rest of it (a 10-car frame); with 0.1 it falls nearly monotonically (0.095 at
the end against 0.129), and on the seed-13 tuning tree the silhouette IoU rose by 0.007 (95 % interval [0.002, 0.013])
with template accuracy unchanged. Fewer fine steps with it still cost template accuracy (10 steps: -7.6 pp, [-13.9,
-1.8]). The measurements: docs/results/2026-11-28_cpu/session4/cost/README.md, session5/cost/README.md and
session6/cost/README.md.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field

import torch
from torch import Tensor

from sdn3d.geometric.lamps import border_side
from sdn3d.geometric.losses import outside_image_mask, render_silhouettes, reprojection_error
from sdn3d.geometric.refine import adam_fit
from sdn3d.image_ops import crop_intrinsics, crop_windows, pixel_centre_boxes, square_crop_window
from sdn3d.math3d.camera import Intrinsics, as_intrinsics_matrix
from sdn3d.math3d.ffd import expand_half_ffd, ffd_deform
from sdn3d.math3d.transforms import object_to_camera
from sdn3d.meshes.bank import MeshBank, default_bank
from sdn3d.meshes.templates import CLASS_TEMPLATES, TEMPLATE_DIMENSIONS
from sdn3d.render.settings import SoftSilhouetteSettings
from sdn3d.render.silhouette import silhouette
from sdn3d.render.soft import kernel_threads

__all__ = ["FitSettings", "FitResult", "FitChoice", "FitRequest", "fit_to_masks", "fit_many", "choose_again",
           "road_start", "estimate_camera_height", "lane_prior",
           "allowed_templates", "CAR_DIMS", "PLAUSIBLE_SIZE_FACTOR", "HYPOTHESES"]

#: Mean KITTI car ``(l, h, w)`` in metres: the size a fit starts from without a usable prediction.
CAR_DIMS = (3.88, 1.53, 1.63)
#: A predicted size is taken (start and prior) when each of its dimensions is within this factor of
#: :data:`CAR_DIMS`: vans and small lorries (7.2 x 3.2 x 2.4 m in the synthetic family) included, a broken prediction
#: (a 30 m car, a 0.5 m one) not. The first factor, 1.6, reset good predictions of large vans to a mean car's size,
#: which their length then stayed near (scale error 3.3 m on such objects of a tuning tree).
PLAUSIBLE_SIZE_FACTOR = 2.5
#: Starting yaws: offsets added to the first start (prediction or facing away): itself, reversed, the two sides.
YAW_OFFSETS = (0.0, math.pi, math.pi / 2, -math.pi / 2)
#: Two fits are end for end of each other when their yaws differ by 180 degrees give or take this (radians).
FACING_AXIS = math.radians(30)
#: A fit's end-for-end counterpart is believed clearly more when its belief is higher by this: with the default
#: belief (``cos`` of the yaw's difference to the first start) where the start lies within 75 degrees of it; a
#: start nearly across the axis has no say on the end. On the seed-13 tuning tree any margin from 0 to 1 chose the
#: same fits.
FACING_MARGIN = 0.5
#: Names of the fine stage's hypotheses (:attr:`FitResult.hypothesis` indexes them; the search's ``k``-th best start
#: is ``4 + k``). The mirrored two are tried where ``FitSettings.mirror`` asks and an appearance belief is given.
HYPOTHESES = ("prediction", "prediction flipped end for end", "prediction mirrored about the line of sight",
              "prediction mirrored and flipped")
#: How many of :data:`HYPOTHESES` a fit without the mirror (``FitSettings.mirror`` false) tries: the search's
#: ``k``-th best start is then ``2 + k``.
UNMIRRORED = 2


@dataclass(frozen=True)
class FitSettings:
    """How :func:`fit_to_masks` searches (module doc).

    Args:
        camera_height: the road plane's ``y`` in the camera frame, metres (y down; KITTI's camera is 1.65 m up);
            None: measured in the image from the predicted cars (:func:`estimate_camera_height`).
        default_camera_height: the height without a prediction to measure it from.
        camera_height_range: the measured height is clamped to this ``(low, high)``.
        coarse_size, coarse_steps: crop side (px) and Adam steps of the search over all starts.
        coarse_faces: the search over all starts draws each template cut to at most this many faces
            (:meth:`~sdn3d.meshes.bank.MeshBank.simplified`; 0: the full meshes).
        fine_size, fine_steps: crop side and Adam steps of the ``keep`` best starts, with the FFD.
        coarse_survivors: after the first third of ``coarse_steps``, only this many best starts of each object go
            on searching (the others keep their loss so far and drop out; 0: every start searches to the end).
        fine_faces: the fine stage fits each template cut to at most this many faces (0: the full meshes); the
            winner's IoU is measured with its full mesh, the FFD and size it was fitted with.
        keep: hypotheses per object that go on to the fine stage.
        tie: fits whose final loss is within this share of the best one are equally good; the yaw nearest the
            first start decides among them.
        facing_tie: a fit facing the end the appearance believes (module doc, step 2) beats a better one on its axis
            facing the other end unless that one's loss is lower by more than this share (0: only ``tie``). The
            silhouette hardly tells front from back, and lower losses of the reverse end come from a template or a
            size that fits better, not from the end: on a seed-13 tuning tree (ground-truth masks and boxes, 442
            cars and vans, the demo-budget MultiBin branch with the lamp cue) the fit turned 23 cars end for end
            with 0, 17 with 0.25, 16 with 0.5, 17 with 1 or more (docs/results/2026-11-28_cpu/session3/flips).
        mirror: two more fine hypotheses: the prediction mirrored about the line of sight (``alpha -> pi - alpha``,
            ``alpha = ry - ray`` with ``ray`` the angle of the ray through the prediction's place: the same end seen,
            its front pointing to the other side) and that mirror's end-for-end flip. A car seen nearly end on casts
            nearly the same outline either way and the branch's bins sit near ``alpha = +-90`` degrees, so a search
            that starts at the prediction stays on its side of the ray. Tried only with a ``yaw_belief`` (the
            appearance's, e.g. the lamps' side): the nearness to the start cannot tell a mirror (a start 90 degrees
            off is nearer the truth's mirror than the truth).
        appearance: the box objects' fit believes the geometric branch's appearance at each hypothesis' axis
            (:func:`~sdn3d.geometric.facing.facing_belief`: the lamps' evidence and the MultiBin bins) rather than
            the nearness to its start. Without the mirror it made as many flips either way on the seed-13 tuning tree
            (16 of 442); with it, it is what tells the mirror apart (the lamps' side: which end lies left), so on
            (docs/results/2026-11-28_cpu/session4/poses).
        cut_inward: a car cut by the image's left or right border drops the fits whose near end points inwards
            by more than this (module doc, step 2: ``side * sin(2 alpha) < -cut_inward``), unless all would or the
            fit left is believed less; in ``[0, 1]``, 1 drops none. On the Table 1 tuning trees 31, 35 and 37
            (session 21's demo weights, ground-truth masks, an oracle), 0.2 without the belief's guard took the
            side-cut cars' median yaw error from 24 to 13 degrees but turned 6 fits end for end, 0.5 to 17 with 2;
            0.2 with the guard to 15, turning none, and on predicted proposals from 23 to 16
            (docs/results/2026-11-30_cpu/session23/inward).
        lr: Adam learning rate (x, log z, log dims; the yaw takes ``2 lr``).
        margin: the crop window grows the box by this share on each side.
        sigma: soft-silhouette softness, px^2.
        dims_reg, yaw_reg, ffd_reg: weights of the size prior, the yaw prior and the FFD's ``mean(phi^2)``.
        lane_reg, lane_width_deg: weight and reach (degrees) of :func:`lane_prior`, the pull towards the road's axis
            for the objects given one (``road_ry``) whose outline is sharp: the box objects' (GrabCut's) masks and
            the ground truth's (an oracle). ``proposal_lane_reg`` is the weight for the semantic branch's proposals
            (a caller's :attr:`FitRequest.lane_reg`). On tuning tree 39 (session 38's
            demo weights, 105 cars of 40 frames) 0.1 and 15 took the proposals' median yaw error from 14.6 to 1.9
            degrees (over 20 degrees: 40 % to 3 %; 64 cars better by over 5 degrees, 2 worse) and the turns' PSNR gain
            over the 2D paste by +0.27 dB [-0.12, +0.55] (Table 1, photo appearance); on tree 35, +0.02 [-0.11,
            +0.18]. A plain ``sin^2`` pull (no reach) of 0.1 gained less (4.3 degrees). On a tree whose parked cars
            were turned up to 60 degrees off their lane, the sharp ground-truth masks' fit with it lost those cars'
            yaw (median 3.8 -> 26 degrees), so session 38 fitted the ground truth's masks and the box objects
            without it (docs/results/2026-12-02_cpu/session38/lane). A car seen end-on, though, has an outline that
            barely changes with its yaw: on tree 39 (w39), 34 % of the box objects' fits and of the ground-truth
            masks' were over 20 degrees off. With the weaker ``lane_reg`` 0.03 they were 13 % and 7.6 %; on the
            askew tree, 16 % and 12.5 % of all cars (23 % and 14 % without), the askew cars among them worse (55 % and
            38 %; 0.1: 69 % and 55 %) (docs/results/2026-12-03_cpu/session39/sharp).
        proposal_lane_reg: :attr:`lane_reg` for the semantic branch's proposals, whose rounded outlines fit many
            yaws about equally well (the 0.1 of session 38 above).
        ffd_step: the FFD's Adam step as a share of ``lr`` (its control values are its own scale: with the full
            step the fine stage's loss jumped up at its first step and swung for the rest of it).
        parts: the objects are fitted in up to this many groups of whole objects (:func:`_in_parts`), one per torch
            thread the caller has, each on its own thread; one thread: one group. Each group's fit is its objects' fit
            alone: groups change the order of float operations only (seed-13 tuning tree, 146 cars and vans in
            frames of 1-9: 145 fits bit-identical with 1 and 2 groups, the last 3e-6 degrees off). Two groups on one
            thread would cost 10-20 % more CPU time in the fit (each pays a stage's per-step Python once).
        cull_backfaces: the Adam steps of both stages draw only the faces facing the camera (the templates are
            closed, so those cover the outline; about half the soft raster's (face, pixel) pairs), while the final
            losses that rank the hypotheses (the search's survivors, its ``keep`` best, the winner) draw every face.
            Ranked with the culled silhouettes too, template accuracy fell by 7 points on the seed-13 tuning tree;
            ranked with every face it held (docs/results/2026-11-28_cpu/session6/cost). Off by default: it cut the
            fit's CPU time by a third, but on the real frame of ``tests/data`` it turned the black car to its mirror
            about the line of sight (-92 -> -56 degrees), and on the seed-13 tuning tree it broke 2 flips and fixed
            none.
        template_size_reg: weight of ``|log d - log d_t|^2``, the size's departure from the typical size of the
            template it is drawn with (:data:`~sdn3d.meshes.templates.TEMPLATE_DIMENSIONS`; only for a bank of the
            templates). A 4 m car fits a pickup's silhouette from behind, but it is not a pickup: on a seed-7 tuning
            tree 0.1 chose the right template for 53 % of 38 cars and vans against 18 % without (0.03: 21 %, 0.3:
            45 %), with no measured change in scale or orientation.
        shape_reg: weight of the change of the size's proportions (the size moves as one scale of the start's
            proportions plus a deviation per dimension; 0: each dimension as free as the others).
        silhouette: ``soft`` (SoftRas) or ``straight_through`` (hard values, soft gradient: the L1 optimum is the
            true outline, not a shrunken one; :mod:`sdn3d.render.silhouette`).
        poor_iou: a fit below this silhouette IoU with its mask is flagged as poor.
        join_overlap: the semantic branch's proposals whose masks touch and whose fitted footprints on the road share
            at least this share of the smaller one are one car: the de-render joins them and fits the union
            (:func:`sdn3d.proposal_fit.footprint_joins`; the box objects and ground-truth masks are never joined);
            None: no join. On the seven Table 1 tuning trees (session 21's demo weights) the touching pairs of
            one car's parts shared up to 0.72 (7 of 42 at 0.45 or more, half of them nothing: the parts fitted
            side by side), those of two cars up to 0.43 (docs/results/2026-11-30_cpu/session27/join40).
        unsure_vehicle: the fit of the semantic branch's proposals ignores the pixels whose vehicle probability (its
            softmax's thing classes together) lies within this of 0.5, inside a mask or out: a mask spills past its
            car (pixel precision 0.77 against recall 0.85 on a tuning tree) where the branch is unsure, and a
            silhouette fitted to the spill turns. With session 36's demo weights, 0.2 turned 5 cars of 409 the right
            way and 1 the wrong way on the tuning trees (p90 yaw error 40.5 -> 36.0 degrees), and on four held-out
            trees 1 and none (296 cars; the matched cars' median yaw error 13.6 -> 12.1 degrees); a soft target
            (the mask times the probability) placed the cars too far
            (docs/results/2026-12-02_cpu/session36/lead/unsure). None: every mask pixel counts. Box objects and
            ground-truth masks are never affected.
        min_mask_pixels, min_mask_side: a mask with fewer pixels, or a bounding box thinner (px), is not fitted: the
            object keeps the branch's prediction (where there is one) and a warning.
    """

    camera_height: float | None = 1.65
    default_camera_height: float = 1.65
    camera_height_range: tuple[float, float] = (1.2, 2.2)
    coarse_size: int = 32
    coarse_steps: int = 12
    coarse_faces: int = 250
    fine_size: int = 64
    fine_steps: int = 16
    fine_faces: int = 600
    coarse_survivors: int = 8
    keep: int = 3
    tie: float = 0.1
    facing_tie: float = 0.5
    mirror: bool = True
    appearance: bool = True
    cut_inward: float = 0.2
    lr: float = 0.05
    margin: float = 0.15
    sigma: float = 0.25
    dims_reg: float = 0.1
    template_size_reg: float = 0.1
    shape_reg: float = 1.0
    silhouette: str = "soft"
    yaw_reg: float = 0.02
    lane_reg: float = 0.03
    proposal_lane_reg: float = 0.1
    lane_width_deg: float = 15.0
    ffd_reg: float = 100.0
    ffd_step: float = 0.1
    cull_backfaces: bool = False
    parts: int = 2
    poor_iou: float = 0.7
    join_overlap: float | None = 0.45
    unsure_vehicle: float | None = 0.2
    min_mask_pixels: int = 24
    min_mask_side: int = 3

    def __post_init__(self) -> None:
        for name in ("coarse_size", "fine_size"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 8:
                raise ValueError(f"FitSettings.{name} must be an integer >= 8, got {value!r}")
        for name in ("coarse_steps", "fine_steps", "keep", "coarse_faces", "fine_faces", "coarse_survivors",
                     "min_mask_pixels", "min_mask_side", "parts"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < (1 if name in ("keep", "parts") else 0):
                raise ValueError(f"FitSettings.{name} must be a non-negative integer (keep, parts >= 1), got {value!r}")
        for name in ("coarse_faces", "fine_faces"):
            if 0 < getattr(self, name) < 4:
                raise ValueError(f"FitSettings.{name} must be 0 (the full meshes) or at least 4, got "
                                 f"{getattr(self, name)}")
        for name in ("camera_height", "default_camera_height", "lr", "sigma", "ffd_step", "lane_width_deg"):
            value = getattr(self, name)
            if name == "camera_height" and value is None:
                continue
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"FitSettings.{name} must be a positive number, got {value!r}")
        for name in ("margin", "dims_reg", "template_size_reg", "shape_reg", "yaw_reg", "lane_reg", "proposal_lane_reg",
                     "ffd_reg", "tie", "facing_tie"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ValueError(f"FitSettings.{name} must be a finite number >= 0, got {value!r}")
        for name in ("appearance", "mirror", "cull_backfaces"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"FitSettings.{name} must be true or false, got {getattr(self, name)!r}")
        if self.silhouette not in ("soft", "straight_through"):
            raise ValueError(f"FitSettings.silhouette must be 'soft' or 'straight_through', got {self.silhouette!r}")
        low_high = self.camera_height_range
        if (not isinstance(low_high, (tuple, list)) or len(low_high) != 2
                or not all(isinstance(v, (int, float)) and math.isfinite(v) and v > 0 for v in low_high)
                or low_high[0] > low_high[1]):
            raise ValueError(f"FitSettings.camera_height_range must be (low, high) with 0 < low <= high, got "
                             f"{low_high!r}")
        object.__setattr__(self, "camera_height_range", (float(low_high[0]), float(low_high[1])))
        if isinstance(self.cut_inward, bool) or not (isinstance(self.cut_inward, (int, float))
                                                     and 0 <= self.cut_inward <= 1):
            raise ValueError(f"FitSettings.cut_inward must be in [0, 1], got {self.cut_inward!r}")
        if not (isinstance(self.poor_iou, (int, float)) and 0 <= self.poor_iou <= 1):
            raise ValueError(f"FitSettings.poor_iou must be in [0, 1], got {self.poor_iou!r}")
        if self.unsure_vehicle is not None and (isinstance(self.unsure_vehicle, bool) or not (
                isinstance(self.unsure_vehicle, (int, float)) and 0 < self.unsure_vehicle <= 0.5)):
            raise ValueError(f"FitSettings.unsure_vehicle must be in (0, 0.5] or None, got {self.unsure_vehicle!r}")
        if self.join_overlap is not None and (isinstance(self.join_overlap, bool) or not (
                isinstance(self.join_overlap, (int, float)) and 0 < self.join_overlap <= 1)):
            raise ValueError(f"FitSettings.join_overlap must be in (0, 1] or None, got {self.join_overlap!r}")

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass
class FitResult:
    """Output of :func:`fit_to_masks` (one row per object, CPU tensors).

    Attributes:
        template: ``(N,)`` long, the winning template; dims ``(N, 3)`` ``(l, h, w)``; ry ``(N,)``;
        location: ``(N, 3)`` bottom-face centre (``y = camera_height``); phi: ``(N, 64, 3)`` FFD.
        iou: ``(N,)`` silhouette IoU with the mask at the fine crop; loss: ``(N,)`` the winner's final loss.
        start_ry: ``(N,)`` the first start's yaw (the prediction's, or facing away).
        hypothesis: ``(N,)`` long, the winning fine hypothesis (:data:`HYPOTHESES`: 0 the prediction, 1 its
            end-for-end flip, 2 its mirror about the line of sight, 3 the mirror's flip, ``4 + k`` the search's
            ``k``-th best start; -1: not fitted, the prediction kept).
        fitted: ``(N,)`` bool, False where the mask was too small or thin and the prediction was kept.
        camera_height: the road plane's ``y`` the fit used (metres) and how it was found (``camera_height_source``).
        notes: what the fit could not do normally, per object index (the sentence without the object's name).
        warnings: one line per such object, naming it by its index (``notes`` for a reader).
        choice: the fine stage's fits of every hypothesis, to choose among them again under another yaw belief
            (:func:`choose_again`); None for an empty fit.
    """

    template: Tensor
    dims: Tensor
    ry: Tensor
    location: Tensor
    phi: Tensor
    iou: Tensor
    loss: Tensor
    start_ry: Tensor
    hypothesis: Tensor = field(default_factory=lambda: torch.zeros(0, dtype=torch.long))
    fitted: Tensor = field(default_factory=lambda: torch.zeros(0, dtype=torch.bool))
    camera_height: float = 1.65
    camera_height_source: str = "default"
    notes: dict[int, str] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    choice: FitChoice | None = field(default=None, repr=False)

    def hypothesis_name(self, i: int) -> str:
        """The ``i``-th object's winning hypothesis in words."""
        h = int(self.hypothesis[i])
        return "not fitted (prediction kept)" if h < 0 else HYPOTHESES[h] if h < len(HYPOTHESES) else \
            f"search start {h - len(HYPOTHESES) + 1}"


@dataclass
class FitChoice:
    """What :func:`fit_to_masks`' fine stage leaves to choose from, for ``n`` objects and ``H`` hypotheses each: the
    choice depends on the yaw belief and nothing before it does (the hypotheses, their starts and their fits do not
    read it), so :func:`choose_again` gives under another belief what a new fit would (a lamp reading that changed,
    :func:`sdn3d.derender.derender`), without fitting again.

    Attributes:
        values: the fitted parameters, each ``(n, H, ...)`` (``x``, ``z``, ``ry``, ``dims``, ``phi_half``).
        loss: ``(n, H)`` each fit's final loss; template: ``(n, H)`` long, each fit's template.
        inward: ``(n, H)`` bool, fits facing into a border that cuts the car (:func:`inward_at_border`).
        mask, ign: ``(n, 1, S, S)`` each object's fine crop of its mask and of its ignored pixels; K: ``(n, 3, 3)``
            its crop camera (the winner's IoU is measured there).
        masks: ``(n, H_img, W_img)`` bool the masks fitted (ignored pixels removed: too small or thin ones keep the
            prediction); start_template ``(n,)`` or None, start_location ``(n, 3)`` or None, dims0 ``(n, 3)``, ry0
            ``(n,)``: the starts.
        mirror: whether the mirrored hypotheses were tried (the record's hypothesis index counts them).
        camera_height, camera_height_source, settings: those of the fit; bank: its templates (the winner's IoU is
            measured with them, not the fine stage's simplified ones).
    """

    values: dict[str, Tensor]
    loss: Tensor
    template: Tensor
    inward: Tensor
    mask: Tensor
    ign: Tensor
    K: Tensor
    masks: Tensor
    start_template: Tensor | None
    start_location: Tensor | None
    dims0: Tensor
    ry0: Tensor
    mirror: bool
    camera_height: float
    camera_height_source: str
    settings: FitSettings
    bank: MeshBank

    def rows(self, index: slice | Tensor) -> FitChoice:
        """The choice of the objects ``index`` (a slice or ``(M,)`` indices)."""
        def pick(t: Tensor | None) -> Tensor | None:
            return None if t is None else t[index]
        return FitChoice({k: v[index] for k, v in self.values.items()}, self.loss[index], self.template[index],
                         self.inward[index], self.mask[index], self.ign[index], self.K[index], self.masks[index],
                         pick(self.start_template), pick(self.start_location), self.dims0[index], self.ry0[index],
                         self.mirror, self.camera_height, self.camera_height_source, self.settings, self.bank)


def road_start(boxes: Tensor, intr: Intrinsics, camera_height: float, width: float = CAR_DIMS[2]) -> Tensor:
    """``(N, 3)`` bottom-face centres where the ray through each box's bottom-edge middle meets the road.

    ``boxes (N, 4)`` half-open ``(x0, y0, x1, y1)`` in ``intr``'s pixels. The bottom edge is the car's nearest
    side, so the centre is put ``width / 2`` further; a bottom edge at or above the horizon (``v <= cy``) is taken
    one pixel below it (a very far car).

    >>> intr = Intrinsics(725.0, 725.0, 620.5, 187.0, 1242, 375)
    >>> road_start(torch.tensor([[600.0, 200.0, 640.0, 264.0]]), intr, 1.65, width=0.0).round(decimals=2).tolist()
    [[-0.02, 1.65, 15.64]]
    """
    b = boxes.double()
    u = (b[:, 0] + b[:, 2]) / 2 - 0.5
    v = (b[:, 3] - 0.5).clamp_min(intr.cy + 1.0)
    z = camera_height * intr.fy / (v - intr.cy) + width / 2
    x = (u - intr.cx) * z / intr.fx
    return torch.stack([x, torch.full_like(x, camera_height), z], 1)


def estimate_camera_height(start_location: Tensor | None, settings: FitSettings) -> tuple[float, str]:
    """``(height, source)``: ``settings.camera_height`` when set, else the median ``y`` of the finite predicted
    bottom-face centres ``start_location (N, 3)`` clamped to ``settings.camera_height_range``, else
    ``settings.default_camera_height``.

    >>> estimate_camera_height(torch.tensor([[1.0, 1.52, 10.0], [0.0, 1.58, 20.0], [2.0, 1.5, 30.0]]),
    ...                        FitSettings(camera_height=None))
    (1.52, 'measured: median of 3 predicted cars')
    """
    if settings.camera_height is not None:
        return float(settings.camera_height), "given"
    if start_location is not None and start_location.numel():
        y = start_location[:, 1].double()
        ok = torch.isfinite(start_location).all(1) & (start_location[:, 2] > 0)
        if bool(ok.any()):
            low, high = settings.camera_height_range
            height = min(max(float(y[ok].median()), low), high)
            return round(height, 4), f"measured: median of {int(ok.sum())} predicted cars"
    return float(settings.default_camera_height), "default"


def fit_windows(boxes: Tensor, settings: FitSettings) -> Tensor:
    """``(N, 3)`` the square windows ``(left, top, side)`` that :func:`fit_to_masks` draws and compares the objects of
    half-open ``boxes (N, 4)`` in (``settings.margin`` around each box)."""
    return torch.tensor([square_crop_window(b, settings.margin) for b in pixel_centre_boxes(boxes.float())],
                        dtype=torch.float32).reshape(-1, 3)


def read_pixels(boxes: Tensor, size: tuple[int, int], settings: FitSettings) -> Tensor:
    """``(N, H, W)`` bool: the pixels of an image of ``size (H, W)`` whose mask and ignored values :func:`fit_to_masks`
    reads for each of the objects of ``boxes (N, 4)``: its window (:func:`fit_windows`) and the ring of one pixel
    around it that the bilinear crops' samples reach (:func:`~sdn3d.image_ops.crop_windows`: sample ``u`` lies in
    ``(left - 1/2, left + side - 1/2)``). Its fit is the same whatever the other pixels hold.

    >>> read_pixels(torch.tensor([[2.0, 1.0, 4.0, 3.0]]), (4, 6), FitSettings(margin=0.0))[0].int().tolist()
    [[0, 1, 1, 1, 1, 0], [0, 1, 1, 1, 1, 0], [0, 1, 1, 1, 1, 0], [0, 1, 1, 1, 1, 0]]
    """
    left, top, side = fit_windows(boxes, settings).long().unbind(1)
    x, y = torch.arange(size[1]), torch.arange(size[0])
    cols = (x >= left[:, None] - 1) & (x <= (left + side)[:, None])
    rows = (y >= top[:, None] - 1) & (y <= (top + side)[:, None])
    return rows[:, :, None] & cols[:, None, :]


def allowed_templates(classes: Sequence[str | None] | None, bank: MeshBank, n: int) -> Tensor:
    """``(n, T)`` bool: the meshes of ``bank`` each of ``n`` objects may be drawn with, by its semantic class name
    (``classes``, case ignored; :data:`~sdn3d.meshes.templates.CLASS_TEMPLATES`). A class without a rule, a None
    entry, ``classes`` None or a bank that is not the templates: every mesh.

    >>> from sdn3d.meshes.bank import default_bank
    >>> allowed_templates(["Car", "van", None], default_bank(), 3).int().tolist()
    [[1, 1, 1, 1, 1, 1, 0, 0], [0, 0, 0, 0, 0, 1, 1, 1], [1, 1, 1, 1, 1, 1, 1, 1]]
    """
    everything = torch.ones(n, len(bank), dtype=torch.bool)
    if classes is None or not all(name in TEMPLATE_DIMENSIONS for name in bank.names):
        return everything
    if len(classes) != n:
        raise ValueError(f"classes must name {n} objects, got {len(classes)}")
    for i, name in enumerate(classes):
        rule = CLASS_TEMPLATES.get((name or "").lower())
        if rule is not None:
            everything[i] = torch.tensor([mesh in rule for mesh in bank.names])
    return everything


def _typical_log_dims(bank: MeshBank) -> Tensor | None:
    """``(M, 3)`` log of each template's typical ``(l, h, w)`` (:data:`TEMPLATE_DIMENSIONS`), None unless every mesh
    of ``bank`` is a template."""
    if not all(name in TEMPLATE_DIMENSIONS for name in bank.names):
        return None
    return torch.tensor([TEMPLATE_DIMENSIONS[name] for name in bank.names]).log()


def _wrap(angle: Tensor) -> Tensor:
    return torch.atan2(torch.sin(angle), torch.cos(angle))


def _crops(masks: Tensor, ignore: Tensor, windows: Tensor, size: int, intr: Intrinsics,
           image_size: tuple[int, int]) -> tuple[Tensor, Tensor, Tensor]:
    """``(mask (N, 1, S, S) float, ignore (N, 1, S, S) float, K (N, 4))`` of each window at side ``size``."""
    mask = crop_windows(masks[:, None].float(), windows, size, "bilinear")
    ign = crop_windows(ignore[:, None].float(), windows, size, "bilinear")
    edges = torch.stack([windows[:, 0] - 0.5, windows[:, 1] - 0.5, windows[:, 0] + windows[:, 2] - 0.5,
                         windows[:, 1] + windows[:, 2] - 0.5], 1).float()
    ign = torch.maximum(ign, outside_image_mask(edges, image_size, size))
    return mask, ign, crop_intrinsics(intr, windows, size)


class _Meshes:
    """The meshes of ``M`` hypotheses gathered once for a whole stage: each Adam step only deforms (FFD), places and
    draws them (:func:`~sdn3d.render.objects.pose_meshes` gathers the bank's rows and, with a ``phi``, its FFD basis
    at every call: a tenth of a step's cost in the search). The same vertices as ``pose_meshes`` to the last bit.

    Args:
        bank: the templates; template: ``(M,)`` mesh ids; K: ``(M, 4)`` crop intrinsics; with_ffd: gather the FFD
            basis (without it :meth:`silhouettes` draws the undeformed meshes: ``phi = 0`` deforms nothing).
    """

    def __init__(self, bank: MeshBank, template: Tensor, K: Tensor, with_ffd: bool) -> None:
        self.verts, self.faces = bank.gather(template)  # (M, V, 3), (M, F, 3)
        self.basis = bank.ffd_basis[template] if with_ffd else None  # (M, V, 64)
        # padding vertices stay at the object's centre so padded faces stay degenerate (as pose_meshes does)
        self.real = (torch.arange(self.verts.shape[1]) < bank.num_verts[template][:, None])[..., None]  # (M, V, 1)
        self.K = as_intrinsics_matrix(K, len(template)).float()

    def silhouettes(self, dims: Tensor, ry: Tensor, center: Tensor, phi: Tensor | None,
                    settings: SoftSilhouetteSettings, kind: str) -> Tensor:
        """``(M, S, S)`` silhouettes; ``phi (M, 64, 3)`` is ignored without the basis."""
        verts = self.verts if self.basis is None or phi is None else ffd_deform(self.verts, phi, self.basis)
        cam = torch.where(self.real, object_to_camera(verts, dims, ry, center), center[:, None])
        return silhouette(kind, cam, self.faces, self.K, settings)


@contextmanager
def _one_torch_thread() -> Iterator[None]:
    """Run the block on one torch thread, then give back the caller's count. A stage is thousands of small tensor
    operations: torch's threads wait for each other at each one (and spin while waiting, on a busy machine), so more
    threads cost CPU time and win nothing there (docs/results/2026-11-28_cpu/session5/cost). The soft raster's fused
    kernel, about half a stage and split by whole meshes, keeps the caller's count (:func:`kernel_threads`). The fit
    is then the same whatever the caller's thread count: the kernel's sums do not depend on it."""
    threads = torch.get_num_threads()
    if threads > 1:
        torch.set_num_threads(1)
    try:
        with kernel_threads(threads):
            yield
    finally:
        if threads > 1:
            torch.set_num_threads(threads)


def _stage(bank: MeshBank, template: Tensor, start: dict[str, Tensor], dims0: Tensor, ry0: Tensor, mask: Tensor,
           ign: Tensor, K: Tensor, size: int, steps: int, settings: FitSettings,
           with_ffd: bool, height: float) -> tuple[dict[str, Tensor], Tensor]:
    """Adam on ``M`` hypotheses (rows of every tensor); returns the fitted values and ``(M,)`` final losses.
    ``start``: the rows' starting ``x``, ``z``, ``ry``, ``dims``, ``phi_half``, and optionally ``barred`` ``(M,)``
    bool: rows whose final loss is ``inf`` (a template the object's class does not allow), and ``road`` ``(M,)``: the
    road's axis where each row's object stands (a yaw, NaN: unknown), whose :func:`lane_prior` the loss adds weighed
    by ``lane`` ``(M,)`` (given with ``road``). Without
    the FFD (``with_ffd`` False) the meshes are drawn undeformed (``start['phi_half']`` is not read).
    With ``settings.cull_backfaces`` the Adam steps draw the faces facing the camera only, and the final losses (what
    ranks the hypotheses) every face."""
    x = start["x"].clone().requires_grad_(True)
    log_z = start["z"].log().clone().requires_grad_(True)
    half_ry = (start["ry"] / 2).clone().requires_grad_(True)  # the yaw moves twice as fast as the rest
    # The size: a shared log-scale of the start's proportions plus a log deviation per dimension (``shape_reg``
    # weighs the deviations, ``dims_reg`` the departure from the prior size). With a shared scale, a silhouette that
    # grows the height and width it shows grows the length it hides with them.
    log_start = start["dims"].log()
    log_scale = torch.zeros(log_start.shape[0], 1).requires_grad_(True)
    log_shape = torch.zeros_like(log_start).requires_grad_(True)
    # The FFD moves by a share of the others' Adam step (``settings.ffd_step``): Adam's steps are about ``lr`` in
    # every coordinate at first, and a full one on each of the 96 control values undoes the fit (module doc, Cost).
    ffd_step = settings.ffd_step
    phi_free = (start["phi_half"] / ffd_step).clone().requires_grad_(with_ffd)
    free = [x, log_z, half_ry, log_scale, log_shape] + ([phi_free] if with_ffd else [])
    every_face = SoftSilhouetteSettings((size, size), sigma=settings.sigma)
    steps_draw = SoftSilhouetteSettings((size, size), sigma=settings.sigma, cull_backfaces=settings.cull_backfaces)
    log_dims0 = dims0.log()
    typical = _typical_log_dims(bank)
    log_typical = None if typical is None else typical[template]
    meshes = _Meshes(bank, template, K, with_ffd)
    road, lane = start.get("road"), start.get("lane")

    def objective(sil_settings: SoftSilhouetteSettings = steps_draw) -> Tensor:
        phi_half = phi_free * ffd_step
        log_dims = log_start + log_scale + log_shape
        dims = log_dims.exp()
        center = torch.stack([x, height - dims[:, 1] / 2, log_z.exp()], 1)
        phi = expand_half_ffd(phi_half) if with_ffd else None
        sil = meshes.silhouettes(dims, 2 * half_ry, center, phi, sil_settings, settings.silhouette)
        prior = (settings.dims_reg * (log_dims - log_dims0).square().sum(1)
                 + settings.shape_reg * log_shape.square().sum(1))
        prior = prior + settings.yaw_reg * (1 - torch.cos(2 * half_ry - ry0)) / 2
        if road is not None:
            prior = prior + lane * lane_prior(2 * half_ry, road, settings.lane_width_deg)
        if log_typical is not None and settings.template_size_reg:
            prior = prior + settings.template_size_reg * (log_dims - log_typical).square().sum(1)
        if phi is not None:
            prior = prior + settings.ffd_reg * phi.square().flatten(1).mean(1)
        return reprojection_error(sil, mask, ign) + prior

    with _one_torch_thread():
        adam_fit(free, objective, steps, settings.lr)
        with torch.no_grad():
            loss = objective(every_face)
    if "barred" in start:  # templates the object's class does not allow: never ranked
        loss = torch.where(start["barred"], torch.full_like(loss, math.inf), loss)
    values = {"x": x.detach(), "z": log_z.detach().exp(), "ry": _wrap(2 * half_ry.detach()),
              "dims": (log_start + log_scale + log_shape).detach().exp(), "phi_half": (phi_free * ffd_step).detach()}
    return values, loss


def lane_prior(ry: Tensor, road: Tensor, width_deg: float) -> Tensor:
    """``(M,)`` how far the yaws ``ry (M,)`` lie from the road's axes ``road (M,)`` (yaws; either end, so a car
    driving the other way pays nothing): ``1 - exp(-sin^2(ry - road) / (2 sin^2(width)))``, 0 on the axis and
    nearly 1 beyond about twice ``width_deg`` degrees of it, where a silhouette that says so keeps its pose (a car
    parked askew, one turning); 0 where ``road`` is NaN (unknown). :attr:`FitSettings.lane_reg` weighs it.

    >>> road = torch.zeros(4)
    >>> [round(v, 3) for v in lane_prior(torch.tensor([0.0, math.pi, 0.2618, 1.5708]), road, 15.0).tolist()]
    [0.0, 0.0, 0.393, 0.999]
    """
    off = torch.sin(ry - torch.nan_to_num(road)).square()
    far = 1 - torch.exp(-off / (2 * math.sin(math.radians(width_deg)) ** 2))
    return torch.where(torch.isfinite(road), far, torch.zeros_like(far))


def _search(bank: MeshBank, template: Tensor, start: dict[str, Tensor], dims0: Tensor, ry0: Tensor, mask: Tensor,
            ign: Tensor, K: Tensor, per: int, settings: FitSettings, height: float) -> tuple[dict[str, Tensor], Tensor]:
    """The coarse stage on ``M = N * per`` starts (rows grouped by object): every start for a third of
    ``coarse_steps``, then only the ``coarse_survivors`` best of each object for the rest (a fresh Adam from where
    they are). Returns every start's values and ``(M,)`` final loss; a start that dropped out keeps its values and
    loss at the cut (its loss is then ``inf``: never among the best)."""
    steps, survivors = settings.coarse_steps, settings.coarse_survivors
    first = steps // 3 if 0 < survivors < per and steps >= 3 else steps
    values, loss = _stage(bank, template, start, dims0, ry0, mask, ign, K, settings.coarse_size, first, settings,
                          with_ffd=False, height=height)
    if first == steps:
        return values, loss
    n = loss.shape[0] // per
    rows = (loss.view(n, per).topk(survivors, dim=1, largest=False).indices + torch.arange(n)[:, None] * per).flatten()
    carried = {k: start[k][rows] for k in ("road", "lane") if k in start}  # read by the stages, not fitted
    rest, rest_loss = _stage(bank, template[rows], {k: v[rows] for k, v in values.items()} | carried, dims0[rows],
                             ry0[rows], mask[rows], ign[rows], K[rows], settings.coarse_size, steps - first, settings,
                             with_ffd=False, height=height)
    for k, v in rest.items():
        values[k][rows] = v
    loss = torch.full_like(loss, math.inf).index_copy(0, rows, rest_loss)
    return values, loss


def fit_to_masks(masks: Tensor, boxes: Tensor, intr: Intrinsics, *, ignore: Tensor | None = None,
                 start_ry: Tensor | None = None, start_dims: Tensor | None = None,
                 start_template: Tensor | None = None, start_location: Tensor | None = None,
                 bank: MeshBank | None = None,
                 settings: FitSettings | None = None,
                 yaw_belief: Callable[[Tensor], Tensor] | None = None,
                 classes: Sequence[str | None] | None = None, unsure_pixels: Tensor | None = None,
                 road_ry: Tensor | None = None, lane_reg: Tensor | None = None) -> FitResult:
    """Fit template, size, yaw, position on the road and FFD of ``N`` vehicles to their masks (module doc).

    Args:
        masks: ``(N, H, W)`` bool visible masks in ``intr``'s image.
        boxes: ``(N, 4)`` half-open boxes around them (crop windows and road starts), ``intr``'s pixels.
        ignore: ``(N, H, W)`` bool pixels that do not count for each object (nearer objects), or None.
        start_ry: ``(N,)`` first starting yaw (the geometric branch's prediction); NaN or None: facing away from
            the camera along the ray (``ry = -pi/2``, the back visible).
        start_dims: ``(N, 3)`` starting ``(l, h, w)`` (NaN rows, implausible ones (:data:`PLAUSIBLE_SIZE_FACTOR`) or
            None: :data:`CAR_DIMS`); also the size prior.
        start_template, start_location: ``(N,)`` template (-1: none) and ``(N, 3)`` bottom-face centre of the
            prediction: with ``start_ry`` and ``start_dims`` one more hypothesis of the fine stage (its ``x`` and
            ``z`` on the road plane), and its end-for-end flip another; the locations also measure the camera's
            height (``settings.camera_height=None``).
        bank: the templates (default: the 8 procedural ones); every one is tried.
        settings: the search (default :class:`FitSettings`).
        yaw_belief: maps ``(N, K)`` yaws to ``(N, K)`` scores of how much the appearance believes each (higher: more;
            e.g. :func:`sdn3d.geometric.model.yaw_distribution` of a MultiBin branch's outputs); it decides among
            the fits within ``tie`` of the best. None: the yaw nearest ``start_ry`` does.
        classes: each object's semantic class name (:func:`allowed_templates`: a car is never drawn as a bus, a van
            never as a sedan); None (or a None entry): every template.
        unsure_pixels: ``(N, H, W)`` bool pixels the silhouette loss (and the fit's IoU) leaves out while the mask
            keeps them (the pixels of nearer objects, ``ignore``, leave the mask): where the mask's source is unsure
            (:attr:`FitSettings.unsure_vehicle`); None: none.
        road_ry: ``(N,)`` the road's axis where each object stands, as a yaw (either end; NaN: unknown,
            :func:`sdn3d.road_heading.road_axes`): every hypothesis' loss adds its object's ``lane_reg`` times its
            :func:`lane_prior`; None: no object's.
        lane_reg: ``(N,)`` each object's weight of the lane prior (e.g. :attr:`FitSettings.proposal_lane_reg` for
            the semantic branch's proposals); None: :attr:`FitSettings.lane_reg` for every object.
    """
    settings = settings or FitSettings()
    bank = bank or default_bank()  # shared: its simplified coarse bank is built once per process
    n = masks.shape[0]
    if masks.dim() != 3 or tuple(masks.shape[-2:]) != intr.size:
        raise ValueError(f"masks must be (N, H, W) of the image {intr.size}, got {tuple(masks.shape)}")
    if tuple(boxes.shape) != (n, 4):
        raise ValueError(f"boxes must be ({n}, 4), got {tuple(boxes.shape)}")
    if unsure_pixels is not None and tuple(unsure_pixels.shape) != tuple(masks.shape):
        raise ValueError(f"unsure_pixels must be shaped as masks {tuple(masks.shape)}, got "
                         f"{tuple(unsure_pixels.shape)}")
    if road_ry is not None and tuple(road_ry.shape) != (n,):
        raise ValueError(f"road_ry must be ({n},), got {tuple(road_ry.shape)}")
    if lane_reg is not None and (tuple(lane_reg.shape) != (n,) or not bool((torch.isfinite(lane_reg)
                                                                            & (lane_reg >= 0)).all())):
        raise ValueError(f"lane_reg must be ({n},) finite weights >= 0, got {lane_reg.tolist()}")
    ignore = torch.zeros_like(masks, dtype=torch.bool) if ignore is None else ignore.bool()
    height, height_source = estimate_camera_height(
        None if start_location is None or start_template is None
        else torch.where((start_template >= 0)[:, None], start_location.float(), float("nan")), settings)
    if n == 0:
        empty = torch.zeros(0)
        return FitResult(torch.zeros(0, dtype=torch.long), torch.zeros(0, 3), empty, torch.zeros(0, 3),
                         torch.zeros(0, 64, 3), empty, empty, empty, camera_height=height,
                         camera_height_source=height_source)
    masks = masks.bool() & ~ignore
    image_size = (intr.width, intr.height)
    road = road_start(boxes, intr, height).float()
    ry0 = torch.full((n,), -math.pi / 2) if start_ry is None else start_ry.float().clone()
    ry0 = torch.where(torch.isfinite(ry0), ry0, torch.full_like(ry0, -math.pi / 2))
    allowed = allowed_templates(classes, bank, n)
    dims0 = torch.tensor(CAR_DIMS).expand(n, 3).clone()
    if start_dims is not None:
        given = start_dims.float()
        ratio = (given / dims0).log().abs()
        plausible = torch.isfinite(given).all(1) & (ratio < math.log(PLAUSIBLE_SIZE_FACTOR)).all(1)
        dims0 = torch.where(plausible[:, None], given, dims0)
    windows = fit_windows(boxes, settings)

    # Coarse: every object x template x starting yaw, rows ordered (object, template, yaw).
    t, y = len(bank), len(YAW_OFFSETS)
    per = t * y
    obj = torch.arange(n).repeat_interleave(per)
    template = torch.arange(t).repeat_interleave(y).repeat(n)
    offsets = torch.tensor(YAW_OFFSETS, dtype=torch.float32).repeat(n * t)
    start = {"x": road[obj, 0], "z": road[obj, 2], "ry": _wrap(ry0[obj] + offsets), "dims": dims0[obj],
             "phi_half": torch.zeros(n * per, 32, 3), "barred": ~allowed[obj, template]}
    lane = torch.full((n,), settings.lane_reg) if lane_reg is None else lane_reg.float()
    road = (None if road_ry is None or not bool((torch.isfinite(road_ry) & (lane > 0)).any())
            else road_ry.float())
    if road is not None:
        start["road"], start["lane"] = road[obj], lane[obj]
    # the silhouette loss's ignored pixels; the mask keeps the unsure ones
    loss_ignore = ignore if unsure_pixels is None else ignore | unsure_pixels.bool()
    mask, ign, K = _crops(masks, loss_ignore, windows, settings.coarse_size, intr, image_size)
    coarse_bank = bank.simplified(settings.coarse_faces) if settings.coarse_faces else bank
    values, loss = _in_parts(_search, n, per, settings.parts, coarse_bank, template, start, dims0[obj], ry0[obj],
                             mask[obj], ign[obj], K[obj], per, settings, height)

    # Fine: the prediction itself (its template, place, yaw and size; where there is none, the best start), its
    # end-for-end flip, and the `keep` best starts of each object, with the FFD.
    keep = min(settings.keep, per)
    best = loss.view(n, per).topk(keep, dim=1, largest=False).indices + torch.arange(n)[:, None] * per
    searched = {k: v[best].clone() for k, v in values.items()}  # (n, keep, ...)
    search_template = template[best]
    predicted = {"x": searched["x"][:, 0], "z": searched["z"][:, 0], "ry": ry0, "dims": dims0,
                 "phi_half": torch.zeros(n, 32, 3)}
    own_template = search_template[:, 0]
    if start_template is not None and start_location is not None:
        own = (start_template >= 0) & torch.isfinite(start_location).all(1) & (start_location[:, 2] > 0)
        predicted["x"] = torch.where(own, start_location[:, 0].float(), predicted["x"])
        predicted["z"] = torch.where(own, start_location[:, 2].float().clamp_min(1.0), predicted["z"])
        own = own & allowed.gather(1, start_template.long().clamp_min(0)[:, None])[:, 0]
        own_template = torch.where(own, start_template.long(), own_template)
    mine = [predicted, {**predicted, "ry": _wrap(ry0 + math.pi)}]
    mirror = settings.mirror and yaw_belief is not None
    if mirror:  # about the ray through the prediction's place: alpha -> pi - alpha, and its flip
        mirrored = _wrap(2 * torch.atan2(predicted["x"], predicted["z"]) + math.pi - ry0)
        mine += [{**predicted, "ry": mirrored}, {**predicted, "ry": _wrap(mirrored + math.pi)}]
    starts = {k: torch.cat([h[k][:, None] for h in mine] + [searched[k]], 1) for k in searched}
    if road is not None:
        starts["road"] = road[:, None].expand(n, len(mine) + keep)
        starts["lane"] = lane[:, None].expand(n, len(mine) + keep)
    fine_template = torch.cat([own_template[:, None].expand(n, len(mine)), search_template], 1)
    hyps = keep + len(mine)
    obj = torch.arange(n).repeat_interleave(hyps)
    mask, ign, K = _crops(masks, loss_ignore, windows, settings.fine_size, intr, image_size)
    fine_bank = bank.simplified(settings.fine_faces) if settings.fine_faces else bank
    values, loss = _in_parts(_stage, n, hyps, settings.parts, fine_bank, fine_template.flatten(),
                             {k: v.flatten(0, 1) for k, v in starts.items()}, dims0[obj], ry0[obj], mask[obj], ign[obj],
                             K[obj], settings.fine_size, settings.fine_steps, settings, with_ffd=True, height=height)
    fitted_ry = values["ry"].view(n, hyps)
    inward = inward_at_border(border_side(pixel_centre_boxes(boxes.float()), intr.width), fitted_ry,
                              torch.atan2(values["x"], values["z"]).view(n, hyps), settings.cut_inward)
    choice = FitChoice({k: v.reshape(n, hyps, *v.shape[1:]) for k, v in values.items()}, loss.view(n, hyps),
                       fine_template, inward, mask, ign, K, masks, start_template, start_location, dims0, ry0, mirror,
                       height, height_source, settings, bank)
    return choose_again(choice, yaw_belief)


def choose_again(choice: FitChoice, yaw_belief: Callable[[Tensor], Tensor] | None = None) -> FitResult:
    """:func:`fit_to_masks`' result from its fine stage's fits ``choice`` under the yaw belief ``yaw_belief`` (as
    :func:`fit_to_masks` takes it; None: the yaw nearest the first start): the winner of each object (module doc,
    step 2), its IoU and the record. The same as fitting again with that belief, without the fitting."""
    n = int(choice.loss.shape[0])
    settings, height = choice.settings, choice.camera_height
    fitted_ry = choice.values["ry"]
    if yaw_belief is not None:
        with torch.no_grad():
            belief = yaw_belief(fitted_ry).float()
    else:
        belief = torch.cos(fitted_ry - choice.ry0[:, None])  # 1: the first start's yaw
    fine, inward = choice.loss, choice.inward
    index = _choose(fine, belief, fitted_ry, settings)
    outward = _choose(torch.where(inward & ~inward.all(1, keepdim=True), math.inf, fine), belief, fitted_ry, settings)
    # The border names the axis, not the end: a fit the appearance believes less than the inward winner stays out.
    index = torch.where(belief.gather(1, outward[:, None])[:, 0] >= belief.gather(1, index[:, None])[:, 0],
                        outward, index)
    everyone = torch.arange(n)
    chosen = {k: v[everyone, index] for k, v in choice.values.items()}
    won = choice.template[everyone, index]
    dims, phi = chosen["dims"], expand_half_ffd(chosen["phi_half"])
    location = torch.stack([chosen["x"], torch.full_like(chosen["x"], height), chosen["z"]], 1)
    with torch.no_grad():
        center = torch.stack([chosen["x"], height - dims[:, 1] / 2, chosen["z"]], 1)
        sil = render_silhouettes(choice.bank, won, dims, chosen["ry"], center, phi, choice.K,
                                 SoftSilhouetteSettings((settings.fine_size,) * 2, sigma=settings.sigma))
    keep_px = choice.ign[:, 0] < 0.5
    drawn, target = (sil > 0.5) & keep_px, (choice.mask[:, 0] > 0.5) & keep_px
    union = (drawn | target).flatten(1).sum(1)
    iou = (drawn & target).flatten(1).sum(1) / union.clamp_min(1)
    # The record's index: HYPOTHESES without the mirror's two, then the search's starts.
    hypothesis = (index if choice.mirror else
                  torch.where(index < UNMIRRORED, index, index + len(HYPOTHESES) - UNMIRRORED))
    result = FitResult(template=won.long(), dims=dims, ry=chosen["ry"], location=location, phi=phi,
                       iou=torch.where(union > 0, iou, torch.zeros_like(iou)).float(), loss=fine[everyone, index],
                       start_ry=choice.ry0, hypothesis=hypothesis.long(), fitted=torch.ones(n, dtype=torch.bool),
                       camera_height=height, camera_height_source=choice.camera_height_source, choice=choice)
    _keep_predictions_of_bad_masks(result, choice.masks, choice.start_template, choice.start_location, choice.dims0,
                                   choice.ry0, settings)
    return result


#: The row-wise arguments of :func:`_stage` and :func:`_search` (after the bank): template, start, dims0, ry0, mask,
#: ign, K.
_ROW_ARGS = 7


def _in_parts(stage: Callable[..., tuple[dict[str, Tensor], Tensor]], n: int, per: int, parts: int, bank: MeshBank,
              *args: object, **kwargs: object) -> tuple[dict[str, Tensor], Tensor]:
    """``stage(bank, *args, **kwargs)`` (:func:`_stage` or :func:`_search`, ``per`` rows per object of ``n``) run on
    up to ``parts`` groups of whole objects, one per torch thread the caller has (their first :data:`_ROW_ARGS`
    arguments cut into rows), the groups' outputs joined in order. Objects are fitted independently, so a group's fit
    is the same alone; each group runs on its own Python thread and one torch thread (the tensor operations release
    the GIL, so two groups use two cores). The grouping alone fixes the float operations: the fit is the same at any
    thread count of at least ``parts``."""
    parts = min(parts, torch.get_num_threads())
    bounds = [n * k // parts for k in range(parts + 1)]
    groups = [(lo * per, hi * per) for lo, hi in zip(bounds[:-1], bounds[1:], strict=True) if hi > lo]
    if len(groups) == 1:
        return stage(bank, *args, **kwargs)
    rows, rest = args[:_ROW_ARGS], args[_ROW_ARGS:]

    def group(lo: int, hi: int) -> tuple[dict[str, Tensor], Tensor]:
        cut = [{k: v[lo:hi] for k, v in a.items()} if isinstance(a, dict) else a[lo:hi] for a in rows]
        return stage(bank, *cut, *rest, **kwargs)

    with _one_torch_thread(), ThreadPoolExecutor(len(groups) - 1) as pool:  # each group (and its kernel) on one thread
        later = [pool.submit(group, *g) for g in groups[1:]]
        done = [group(*groups[0])] + [f.result() for f in later]
    values = {k: torch.cat([d[0][k] for d in done]) for k in done[0][0]}
    return values, torch.cat([d[1] for d in done])


def inward_at_border(side: Tensor, ry: Tensor, ray: Tensor, limit: float) -> Tensor:
    """``(N, H)`` bool: which of the yaws ``ry (N, H)`` put a cut car's near end inwards (module doc, step 2):
    ``side (N,)`` the border that cuts each car (-1 left, +1 right, 0 neither: never inwards), ``ray (N, H)`` the
    angle of the ray through each fit's place, ``limit`` :attr:`FitSettings.cut_inward`.

    >>> side, ray = torch.tensor([1.0, -1.0, 0.0]), torch.full((3, 2), 0.5)
    >>> ry = torch.tensor([[-2.07, -0.5], [-2.07, -0.5], [-2.07, -0.5]])  # alpha -150 and -60 degrees (both backs)
    >>> inward_at_border(side, ry, ray, 0.2).tolist()  # at the right border the near end (the back) of -60 is left
    [[False, True], [True, False], [False, False]]
    """
    return side[:, None] * torch.sin(2 * (ry - ray)) < -limit


def _choose(loss: Tensor, belief: Tensor, ry: Tensor, settings: FitSettings) -> Tensor:
    """``(N,)`` the winning hypothesis of each object (module doc, step 2) from the fine stage's ``(N, H)`` losses,
    the appearance's belief in each fit's yaw and the yaws ``ry (N, H)``: the fits that an end-for-end counterpart
    does not beat (believed more by :data:`FACING_MARGIN`, loss within ``facing_tie`` of theirs) compete; the most
    believed of those within ``tie`` of their best loss wins.

    >>> loss = torch.tensor([[1.0, 0.8, 1.2]])  # the best fit (1) is the reverse of fit 0, which is believed more
    >>> belief, ry = torch.tensor([[0.9, -0.9, 0.2]]), torch.tensor([[0.0, 3.1, 1.6]])
    >>> _choose(loss, belief, ry, FitSettings(facing_tie=0.5)).tolist(), _choose(
    ...     loss, belief, ry, FitSettings(facing_tie=0.0)).tolist()
    ([0], [1])
    """
    opposite = torch.cos(ry[:, :, None] - ry[:, None, :]) < -math.cos(FACING_AXIS)  # (N, H, H): row h, column h'
    believed_more = belief[:, None, :] - belief[:, :, None] >= FACING_MARGIN
    no_worse = loss[:, None, :] <= loss[:, :, None] * (1 + settings.facing_tie)
    pool = ~(opposite & believed_more & no_worse).any(2)  # the most believed fit is never beaten: never empty
    reference = torch.where(pool, loss, torch.full_like(loss, math.inf)).amin(1, keepdim=True)
    equal = pool & (loss <= reference * (1 + settings.tie))
    return torch.where(equal, belief, torch.full_like(belief, -math.inf)).argmax(1)


def _keep_predictions_of_bad_masks(result: FitResult, masks: Tensor, start_template: Tensor | None,
                                   start_location: Tensor | None, dims0: Tensor, ry0: Tensor,
                                   settings: FitSettings) -> None:
    """A mask too small or too thin to fit (``min_mask_pixels``, ``min_mask_side``): the object keeps the branch's
    prediction where there is one (``fitted`` False, ``hypothesis`` -1) and gets a warning naming it."""
    pixels = masks.flatten(1).sum(1)
    rows, cols = masks.any(2), masks.any(1)
    side = torch.minimum(rows.sum(1), cols.sum(1))  # rows and columns the mask touches
    for i in range(masks.shape[0]):
        small, thin = int(pixels[i]) < settings.min_mask_pixels, int(side[i]) < settings.min_mask_side
        if not (small or thin):
            continue
        why = (f"its mask has {int(pixels[i])} pixels (< {settings.min_mask_pixels})" if small
               else f"its mask is {int(side[i])} px thin (< {settings.min_mask_side})")
        has_prediction = (start_template is not None and start_location is not None and int(start_template[i]) >= 0
                          and bool(torch.isfinite(start_location[i]).all()))
        if not has_prediction:
            result.notes[i] = f"{why}; no prediction to keep, fitted anyway (unreliable)"
            result.warnings.append(f"object {i}: {result.notes[i]}")
            continue
        result.template[i] = int(start_template[i])
        result.dims[i], result.ry[i] = dims0[i], _wrap(ry0[i])
        result.location[i] = start_location[i].float()
        result.phi[i] = 0.0
        result.iou[i] = 0.0
        result.hypothesis[i], result.fitted[i] = -1, False
        result.notes[i] = f"{why}: not fitted, the geometric branch's prediction kept"
        result.warnings.append(f"object {i}: {result.notes[i]}")


@dataclass
class FitRequest:
    """One caller's objects for :func:`fit_many`: :func:`fit_to_masks`' per-object arguments (same meaning; ``masks``
    ``(N, H, W)`` and ``boxes (N, 4)`` required, the rest optional: ``classes`` each object's semantic class name;
    ``lane_reg`` the weight of the lane prior for all its objects, None: the settings' ``lane_reg``)."""

    masks: Tensor
    boxes: Tensor
    ignore: Tensor | None = None
    start_ry: Tensor | None = None
    start_dims: Tensor | None = None
    start_template: Tensor | None = None
    start_location: Tensor | None = None
    yaw_belief: Callable[[Tensor], Tensor] | None = None
    classes: Sequence[str | None] | None = None
    unsure_pixels: Tensor | None = None
    road_ry: Tensor | None = None
    lane_reg: float | None = None

    def __len__(self) -> int:
        return int(self.masks.shape[0])


def fit_many(requests: list[FitRequest], intr: Intrinsics, *, bank: MeshBank | None = None,
             settings: FitSettings | None = None) -> list[FitResult]:
    """:func:`fit_to_masks` of several callers' objects in one call, one :class:`FitResult` per request (its rows, its
    object indices in ``notes`` and ``warnings``). Each stage then draws every object's hypotheses at once: the
    stages' fixed cost (a chunked raster call and its Python per Adam step) is paid once, not once per caller
    (e.g. :func:`sdn3d.derender.derender`'s proposals and box objects). Objects are fitted independently of each
    other; only the camera height, where it is measured (``settings.camera_height=None``), is measured from all
    requests' predictions together. A missing argument of one request takes the value that means "none" for its
    rows (no ignored pixels, NaN starts, template -1); its yaw belief, where others have one, is the default's
    (the yaw nearest its first start)."""
    sizes = [len(r) for r in requests]
    settings_lane = (settings or FitSettings()).lane_reg
    if len(requests) == 1:
        r = requests[0]
        return [fit_to_masks(r.masks, r.boxes, intr, ignore=r.ignore, start_ry=r.start_ry, start_dims=r.start_dims,
                             start_template=r.start_template, start_location=r.start_location, bank=bank,
                             settings=settings, yaw_belief=r.yaw_belief, classes=r.classes,
                             unsure_pixels=r.unsure_pixels, road_ry=r.road_ry,
                             lane_reg=None if r.lane_reg is None else torch.full((len(r),), float(r.lane_reg)))]

    def joined(name: str, shape: tuple[int, ...], fill: float | int | bool, dtype: torch.dtype) -> Tensor:
        parts = [getattr(r, name) for r in requests]
        return torch.cat([torch.full((len(r), *shape), fill, dtype=dtype) if v is None else v.to(dtype)
                          for r, v in zip(requests, parts, strict=True)])

    masks = torch.cat([r.masks.bool() for r in requests])
    image = tuple(masks.shape[1:])
    start_ry = joined("start_ry", (), math.nan, torch.float32)
    beliefs = [r.yaw_belief for r in requests]
    belief = None
    if any(b is not None for b in beliefs):
        first = torch.where(torch.isfinite(start_ry), start_ry, torch.full_like(start_ry, -math.pi / 2))
        bounds = [sum(sizes[:i]) for i in range(len(sizes) + 1)]

        def belief(ry: Tensor) -> Tensor:  # each request's rows by its own belief, else the default's
            return torch.cat([torch.cos(ry[lo:hi] - first[lo:hi, None]) if b is None else b(ry[lo:hi]).float()
                              for b, lo, hi in zip(beliefs, bounds[:-1], bounds[1:], strict=True)])

    result = fit_to_masks(masks, torch.cat([r.boxes.float() for r in requests]), intr,
                          ignore=joined("ignore", image, False, torch.bool), start_ry=start_ry,
                          start_dims=joined("start_dims", (3,), math.nan, torch.float32),
                          start_template=joined("start_template", (), -1, torch.long),
                          start_location=joined("start_location", (3,), math.nan, torch.float32),
                          bank=bank, settings=settings, yaw_belief=belief,
                          classes=[c for r in requests for c in (r.classes or [None] * len(r))],
                          unsure_pixels=None if all(r.unsure_pixels is None for r in requests)
                          else joined("unsure_pixels", image, False, torch.bool),
                          road_ry=None if all(r.road_ry is None for r in requests)
                          else joined("road_ry", (), math.nan, torch.float32),
                          lane_reg=torch.cat([torch.full((len(r),), settings_lane if r.lane_reg is None
                                                         else float(r.lane_reg)) for r in requests]))
    out, lo = [], 0
    for size in sizes:
        rows = slice(lo, lo + size)
        notes = {i - lo: note for i, note in result.notes.items() if lo <= i < lo + size}
        out.append(FitResult(result.template[rows], result.dims[rows], result.ry[rows], result.location[rows],
                             result.phi[rows], result.iou[rows], result.loss[rows], result.start_ry[rows],
                             result.hypothesis[rows], result.fitted[rows], result.camera_height,
                             result.camera_height_source, notes, [f"object {i}: {note}" for i, note in notes.items()],
                             None if result.choice is None else result.choice.rows(rows)))
        lo += size
    return out
