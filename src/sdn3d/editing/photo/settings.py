"""The photo appearance's settings (:class:`PhotoSettings`), its fill methods and its source-map codes."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from torch import Tensor

from sdn3d.errors import UserInputError

__all__ = ["FILL_METHODS", "RAY_FILLS", "UNSEEN_MODES", "SILHOUETTE_MODES", "AMODAL_MODES", "SHADOW_MODES",
           "GRAIN_MODES", "VERGE_MODES", "VANISHING_MODES", "AUTO_THIN_PX", "SOURCE_NAMES", "SOURCE_COLORS",
           "PATCHMATCH_MAX_SIDE",
           "INPUT", "PHOTO", "MIRROR", "FALLBACK", "FILL", "RECOLORED", "SHADOW", "PART", "DEFAULT", "RELIT",
           "IN_FRONT", "ANOTHER_CAR", "FLAT_CODES",
           "PART_DEFAULTS", "PART_COLORS", "PhotoSettings", "PhotoSettingsError", "source_picture", "part_picture"]


#: How vacated pixels are filled: OpenCV's Telea (fast; the best weight-free fill by L1 and PSNR on a held-out
#: synthetic benchmark's delete and occluder entries, by 0.3-0.5 dB, but it smears bushes and facades across a large
#: hole), PatchMatch (PyPatchMatch: copies texture, plausible road on large holes, slower), ``auto`` (the default: Telea
#: for thin gaps, PatchMatch for large holes), the generator's picture (needs the textural branch) or ``rays``
#: (:mod:`sdn3d.editing.photo.road`: each pixel from the nearest known pixels on its line through the road's vanishing
#: point, so lane markings, kerbs and verges run on through the hole; Telea where no line reaches) or ``learnt`` (the
#: rays' fill with a small net's colour correction inside the hole, :mod:`sdn3d.editing.photo.learnt`, trained on the
#: generator's exact delete pairs).
FILL_METHODS = ("telea", "patchmatch", "auto", "generator", "rays", "learnt")
#: The fills drawn along the road's rays (their removal takes the removed car's effects and vanishing point).
RAY_FILLS = ("rays", "learnt")
#: What a removed car's shadow becomes with ``delete_effects`` and ``fill='rays'`` (:attr:`PhotoSettings.shadow_mode`):
#: ``fill`` (the shadowed road near it joins the hole and is filled along the rays from lit road) or ``relight``
#: (relit by a per-channel gain and a matte first, :func:`~sdn3d.editing.photo.fill.relight_shadow`).
SHADOW_MODES = ("fill", "relight")
#: How ``fill='rays'`` puts the road's grain back (:attr:`PhotoSettings.ray_grain`): at the fixed weight
#: ``ray_texture`` (``fixed``) or at the weight that matches the fine texture of the road around the hole (``match``).
GRAIN_MODES = ("fixed", "match")
#: What ``fill='rays'`` does with a ray whose near side is a verge and whose far side is road
#: (:attr:`PhotoSettings.ray_verge`; :func:`~sdn3d.editing.photo.road.ray_fill`): ``blend`` (both interpolated by
#: distance), ``road`` (the road side alone) or ``edges`` (the road side alone outside the verge's edges continued
#: straight into the hole, the verge inside them: :func:`~sdn3d.editing.photo.road._continued_verge`).
VERGE_MODES = ("blend", "road", "edges")
#: What ``fill='rays'`` does with a hole pixel whose ray runs inside the hole up to the vanishing point (no far side:
#: :attr:`PhotoSettings.ray_vanishing`; :func:`~sdn3d.editing.photo.road.ray_fill`): ``near`` (its near side alone)
#: or ``telea`` (Telea from the pixels around it).
VANISHING_MODES = ("near", "telea")
#: ``fill='auto'``: a hole part at most this many pixels from its edge everywhere is filled by Telea, else PatchMatch.
AUTO_THIN_PX = 6.0
#: How a point of an edited car that neither the photo nor its mirror image saw is drawn
#: (:attr:`PhotoSettings.unseen`): ``parts`` (the default: the same part seen elsewhere on the same car where it
#: faced the camera as the new surface does, a lamp never seen from the other end's lamps; any other part never seen
#: gets its :data:`PART_DEFAULTS` colour) or ``body`` (the car's body colour everywhere: the appearance before vehicle
#: parts existed).
UNSEEN_MODES = ("parts", "body")
#: Which pixels an edited car covers (:attr:`PhotoSettings.silhouette`): ``template`` (its fitted template's, posed)
#: or ``carved`` (the template's, less every point the input's masks rule out: a point whose projection in the
#: input, or its mirror image's across the car's left-right plane, lands on open background is not on the car; the
#: silhouette of one view and the car's symmetry carve the template as a visual hull would).
SILHOUETTE_MODES = ("template", "carved")
#: What an object that stays draws where a removed object freed its hidden part (:attr:`PhotoSettings.amodal`): ``all``
#: (every point, the ones the photo never showed in flat colour) or ``seen`` (the points the photo, its mirror image or
#: the same part elsewhere on the car supply; the flat ones are left to the fill, which carries the surroundings in).
AMODAL_MODES = ("all", "seen")
#: Codes of :attr:`PhotoResult.source`: ``part``: the same part seen elsewhere on the car (for a lamp the photo never
#: showed, the other end's lamps and paint); ``default``: a part the
#: photo never showed, in its :data:`PART_DEFAULTS` colour; ``relit``: road under a removed car's shadow, relit;
#: ``in front``: the input's pixels of a thin thing in front of a car (a pole), kept in front of what an edit drew;
#: ``another car``: a part this car never showed, drawn from the same part of another car in the photo (the tyres
#: of a car seen from behind, from a car seen from the side).
SOURCE_NAMES = ("input", "photo", "mirror", "fallback", "fill", "recolored", "shadow", "part", "default", "relit",
                "in front", "another car")
#: Colour of each source code in :func:`source_picture` (sRGB uint8).
SOURCE_COLORS = ((40, 40, 40), (60, 170, 75), (70, 120, 230), (230, 80, 60), (240, 200, 60), (200, 90, 220),
                 (120, 120, 120), (150, 220, 230), (250, 140, 20), (170, 150, 110), (255, 255, 255), (40, 140, 130))
INPUT, PHOTO, MIRROR, FALLBACK, FILL, RECOLORED, SHADOW, PART, DEFAULT, RELIT, IN_FRONT, ANOTHER_CAR = range(12)
#: Source codes that are flat paint rather than the photo's texture.
FLAT_CODES = (FALLBACK, DEFAULT)
#: sRGB albedo of a vehicle part the photo never showed (indexed by :class:`~sdn3d.meshes.parts.Part`), shaded by
#: the fitted light for its normal. Plain defaults, not learnt: body mid grey (only when no paint is seen at all),
#: glass dark blue-grey, tyres near black, front end (head lights and grille) light grey, tail lights red, plates
#: near white.
PART_DEFAULTS = ((0.5, 0.5, 0.5), (0.10, 0.12, 0.15), (0.05, 0.05, 0.05), (0.55, 0.55, 0.52), (0.55, 0.07, 0.05),
                 (0.85, 0.85, 0.80))
#: PatchMatch runs on crops at most this many pixels on a side (larger ones are filled at a coarser scale).
PATCHMATCH_MAX_SIDE = 256


class PhotoSettingsError(UserInputError):
    """A bad photo-appearance setting (``photo.*`` of ``sdn3d-edit``)."""


@dataclass(frozen=True)
class PhotoSettings:
    """How :func:`render_photo` draws an edit.

    Attributes:
        fill: :data:`FILL_METHODS` for vacated pixels (default ``rays``: on vacated region + shadow band of exact
            delete pairs, ground-truth geometry, +1.7 dB over ``auto``/PatchMatch on the seed-33 tuning tree, +0.03 and
            +1.7 dB on held-out seeds 2029 and 2043, with lower L1 and residual shadow on all three;
            docs/results/2026-11-28_cpu/session3/deletes/). With ``rays`` a removed car always takes its effects
            (``delete_effects``' silhouette and shadow).
        depth_tolerance: a carried point counts as visible when the source rasterization's depth there is
            within this fraction of its own depth (plus 5 cm).
        min_view_cos: ... and when the input saw its surface at least this squarely (cosine between the surface
            normal and the line of sight): a side seen edge-on in the input covers a pixel or two there and would be
            stretched over the whole side when the car turns.
        view_stretch: ... unless the edit shows that surface at most this many times as squarely as the input did (a
            move that keeps the view: nothing is stretched); a huge value: ``min_view_cos`` alone decides.
        mask_erode_px: input pixels the upsampled instance masks are eroded by before they vouch for a pixel
            (None: one working pixel, ``ceil(1 / scale)``).
        hole_dilate_px: input pixels a vacated footprint grows by (its anti-aliased rim, its shadow's edge).
        shadow_band: height of the road band below a vacated footprint (its old contact shadow) as a fraction
            of the footprint's height.
        leftover_reach: a removal also fills the pieces of a removed object that its mask and fitted silhouette
            missed (a side mirror), up to this share of its mask's height past the hole: pixels there that a flood from
            farther out, across colour steps of at most ``leftover_step``, does not reach, in pieces attached to the
            car beside its upper half (:func:`~sdn3d.editing.photo.fill.leftover_pieces`), filled by Telea after the
            hole so that its fill stays the same (0: none). On the real frame of ``tests/data`` the black car's mirror
            stayed behind as a dark speck; on the tuning trees' deletes no PSNR changed
            (docs/results/2026-11-30_cpu/session21/speck/).
        leftover_step: ... the largest colour step (CIE Lab, each channel) the flood crosses.
        contact_shadow: darkening of the road under a moved object at its new place (0: none).
        relight: re-shade transferred pixels for their new normals (:func:`fit_light`; False, the default: on the
            tuning seed's exact turn pairs the fitted light cost every bin 1-2 dB, the unseen surfaces carry the
            shading of the car's own pixels that faced the same way instead, docs/results/2026-11-28_cpu/session3/).
        inpaint_radius: Telea's neighbourhood (input pixels).
        max_level: deepest pyramid level sampled when an object shrinks (2**level smaller).
        unseen: :data:`UNSEEN_MODES` for what neither the photo nor the mirror saw (default ``parts``).
        part_smoothing: with ``unseen='parts'``, a never-seen pixel drawn from examples (codes ``part``, ``another
            car``) takes the barycentric mix of its face's three corner colours (Gouraud), not its own lookup's: each
            corner's colour is the mean of the part lookup at the pixel's own point and part with the normal of each
            face of the vertex's smoothing fan (:func:`~sdn3d.editing.photo.transfer._corner_groups`: faces joined
            by edges of one part within ``part_smoothing_crease_deg``, the greenhouse's glass told from the body per
            face, :func:`~sdn3d.editing.photo.transfer._fan_labels`: no corner on the belt line mixes the window's
            and the paint's lookups), so each face keeps on average the examples main's lookup chose for it. One
            normal per coarse template face gave each face its own examples, a turned car's new side showed facets in
            stair steps (issue 41, docs/results/2026-12-01_cpu/session29/gouraud29/, session30/gouraud30/).
            False: each pixel its own lookup (the pictures before it, bit for bit).
        part_smoothing_crease_deg: ... an edge whose faces' normals lie more than this many degrees apart splits the
            fans (a roof against a side stays a sharp edge), in (0, 180]. 35: on the real frame's two turned cars the
            colour step at face edges fell from 6.2 to 2.1 times the step within a face (25: 2.7, 45: 1.9); on the
            tuning trees' turns of 45 degrees and more (seeds 31 and 33, ground-truth geometry) +0.06 dB pooled with
            L1 unchanged (session 29, glass and body one fan: 45 gave +0.10 dB but L1 up to +0.0010, 30: +0.03 dB).
        silhouette: :data:`SILHOUETTE_MODES`, which pixels an edited car covers.
        amodal: :data:`AMODAL_MODES`, what a staying object draws where a removed one freed its hidden part.
        mask_view_deg: with ``silhouette='carved'``, a moved car whose view turned by at most this many degrees (its
            yaw against the line of sight) also covers what the input's mask, moved by the 2D map its box makes,
            adds to its template (0: nothing added).
        paste_max_iou: ... and only where its fitted template's outline in the input overlaps its mask at an IoU of at
            most this (1: whatever the fit): a template that matches its mask is the car's own outline, and its 3D
            transfer draws the new view's perspective, which the 2D map only approximates.
        delete_effects: a removed (deleted or moved) object takes its effects with it: its fitted silhouette joins
            the hole, the road part of the hole (below its footprint's far edge) is filled from road-like pixels only,
            and with ``delete_shadow`` its cast shadow (found from its box, the fitted light and the road plane) is
            relit rather than repainted (False, the default: the hole is its mask and a band below, filled from
            everything; on the tuning trees the two disagree, docs/results/2026-11-28_cpu/issue41/). ``fill='rays'``
            and ``'learnt'`` always take the effects (:data:`RAY_FILLS`), so this changes the other fills only.
        delete_shadow: relight a removed object's shadow (with ``delete_effects``).
        cast_shadow: a moved object casts its shadow at its new place (its posed mesh cast along the fitted light
            onto its ground plane, darkened by the per-channel gain of its shadow in the input) and its old shadow
            is relit (as ``delete_effects`` does for a deleted one); False: only the contact shadow.
        cast_blur: the cast shadow's penumbra (Gaussian sigma, input pixels).
        ray_blur: ``fill='rays'``: Gaussian sigma (input pixels) of the normalised blur of the pixels the rays read.
        ray_texture: ``fill='rays'``: weight of the road's fine texture (the sources' high-pass mirrored across the
            hole's edge) added to the fill (0: smooth along the rays).
        ray_span: ``fill='rays'``: source pixels averaged along each ray from the hole's edge outward.
        ray_grain: :data:`GRAIN_MODES` (``fill='rays'``): ``fixed`` puts the grain back at ``ray_texture``; ``match``
            (the default) at the weight (0 to 3; ``ray_texture`` unused) that gives the fill's road the fine texture
            (mean absolute luma Laplacian) of the road 8-40 pixels around the hole
            (:func:`~sdn3d.editing.photo.road.ray_fill`): on the real frame of ``tests/data`` the red car's delete
            had 0.44 of its road's texture at the fixed 0.25, 1.02 matched; on the seed-33 tuning deletes it costs
            0.1 dB (docs/results/2026-11-28_cpu/session4/deletes/).
        shadow_mode: :data:`SHADOW_MODES`, with ``delete_effects``, ``delete_shadow`` and ``fill='rays'``.
        shadow_light: road darker than this share of the road's lightness on its row is shadow (``fill='rays'``
            with ``delete_effects``: never a ray's source; with ``shadow_mode='fill'``, the removed car's own joins
            the hole).
        shadow_reach: ``shadow_mode='fill'``: the removed car's shadow is also filled where it runs on past the
            hole's edge outside the region its fitted box gives (a box that sits off its car), in pieces within this
            share of the hole's height of it, wholly in its lower half, continuing shadow the hole covers
            (:func:`~sdn3d.editing.photo.fill.shadow_pieces`), by Telea after the hole so that its fill stays the
            same (0: none). On the real frame of ``tests/data`` both cars' deletes left their shadow's dark tip
            beside a wheel (docs/results/2026-11-30_cpu/session21/shade/).
        faint_light: ``shadow_mode='fill'``: road near the removed car (its shadow's search region, lower half of the
            hole's rows) lighter than ``shadow_light`` but darker than this share both of its row's lit road and
            of the lit road beside it along the row (blurred over 1.5 px), in pieces touching the filled hole and
            shadow, is the faint edge of its shadow (penumbra, blocked skylight) and is relit by the gain that
            brings it to the darker of the two references
            (:func:`~sdn3d.editing.photo.fill.relight_faint_shadow`), before the rays fill the hole (so they do not
            carry it in). 0: none (the behaviour before); else above ``shadow_light``, at most 1. 0.98 (default):
            chosen on the tuning counterfactual trees with the row's reference alone, where the predicted deletes'
            residual darkening fell from 5.75 / 3.83 / 5.05 % to 4.34 / 3.35 / 4.32 % with hole PSNR up (0.9:
            5.33 / 3.69 / 5.02 %; 1.0 within 0.1 point of 0.98, and relights road darker than its row's median,
            its own grain); Table 1's deletes and occluder removals not worse. With both references, on the
            held-out tree 2273: 4.92 -> 3.74 % (truth's 1.70 %), hole PSNR +0.009 dB [+0.000, +0.018]
            (docs/results/2026-11-30_cpu/session27/shadow41/).
        grow_min_seen: an object behind a removed one is completed into the freed pixels (amodal completion) only if
            at least this many of its pixels show in the input (eroded mask); one the input never showed is left to
            the fill, as are freed pixels its own fitted silhouette claims in front of the removed object (its fit
            overshoots there). 1 (default): on the seed-33 tuning deletes a never-seen car drawn in its parts'
            default colours had twice the fill's error there (0: every object grows wherever its silhouette lies,
            the behaviour before).
        grow_predicted_share: an object whose mask the semantic branch predicted (a scene de-rendered with
            ``proposals=semantic``, less the objects named by a box: :func:`~sdn3d.proposals.predicted_masks`) is
            completed into the freed pixels only while the pixels it draws there (with ``amodal='seen'`` the ones
            the photo, its mirror or the same part supplies) are at most this share of the pixels its mask shows in
            the input; past it none is drawn and the fill keeps them all, as the 2D paste does (0: no
            predicted object is completed; a huge value: every one is, the behaviour before). Ground-truth masks and
            box objects are not capped. Why: a predicted mask is a blob that often joins two cars or splits one and
            the pose fitted to it is a guess (median yaw error 38 degrees against 3.8 on ground-truth masks,
            docs/results/2026-11-30_cpu/session21/lead/), and the more a completion adds to what the photo showed of
            the car, the more of it rests on that pose. 0.5 (default): on the predicted rows of the Table 1 trees
            31/35/37 and the spent held-out trees 2193/2205/2211, the completions adding more than half the car's
            shown pixels lost to the 2D paste's fill there 20 times in 22 (-18.6 dB summed over entries; a distant car's
            template drawn as a dark block across the road), those adding less lost smaller amounts (15 wins, 39
            losses, -3.6 dB), while with ground-truth masks (an oracle) the larger ones won 22 times in 23; no
            completion at all (0) lost held-out 2205's deletes (docs/results/2026-11-30_cpu/session22/occl/), where
            the small completions were right (docs/results/2026-11-30_cpu/session23/rmpred/).
        keep_in_front: thin things in front of a car that its mask leaves out (a pole, a sign post:
            :func:`~sdn3d.editing.photo.occluders.thin_occluders`) stay in front in every edit (False: they are the
            car's, and a delete fills them).
        ray_marks: ``fill='rays'``: a ray whose one side is a marking (near grey, more than this much lighter in luma
            than its own neighbourhood) and whose other side is not takes that side alone
            (:func:`~sdn3d.editing.photo.road.ray_fill`'s ``marks``), so a dash seen on one side of the hole is not
            drawn out into a long stripe along its line (0: the two sides interpolated everywhere).
        ray_haze: ``fill='rays'``: weight of the road's change of colour with its row (fog and haze lighten it towards
            the horizon; :func:`~sdn3d.editing.photo.road.road_haze`, fitted on the road around the hole) added to each
            filled pixel from its sources' rows to its own, so near road carried up towards the vanishing point takes
            the far road's fog (0: the sources' colours as they are).
        ray_haze_airlight: ``ray_haze``'s fog check: the correction applies only where the fitted fog's colour is
            within this (sRGB, any channel) of the far picture's, the median colour of the rows around the horizon
            (fog takes everything far to its own colour; a far road lighter for another reason, a wet sheen, a lit
            patch or the end of a shade, fits a "fog" the far picture does not show). 1: no check. On the tuning
            trees 0.25 kept every fog and rain gain on the counterfactual deletes and dropped the clear-weather fits
            and a rain delete whose fit had run to the horizon (docs/results/2026-11-28_cpu/session7/haze/).
        ray_verge: :data:`VERGE_MODES` (``fill='rays'``): a ray whose near side (away from the vanishing point) is a
            verge (grass, foliage, a hedge: Lab chroma far from the road's and from grey, or dark) and whose far side
            is road, on the ground near the removed car and with its far side resolved, takes the far side's road
            alone (``road``) or blends the two (``blend``; :func:`~sdn3d.editing.photo.road.ray_fill`). On the real
            frame of ``tests/data`` the black car's delete drew a pale band of the verge across the far lane with
            ``blend``; the tuning deletes: docs/results/2026-11-29_cpu/session14/roadfill/. ``edges``: as ``road``
            outside the verge's edges continued straight into the hole, and the verge (mirrored across the hole's
            edge) inside them: with ``road`` the same delete ended the traffic island right of the car in a straight
            vertical edge where the hole began (docs/results/2026-11-30_cpu/session21/island/).
        ray_vanishing: :data:`VANISHING_MODES` (``fill='rays'``): a hole pixel whose ray runs inside the hole all the
            way to the vanishing point (the hole covers that point: a car straight ahead) has no far side; ``telea``
            fills it by Telea from the pixels around it (the rays' fill included), ``near`` from its near side alone,
            which carries the near road's colour up to the horizon and the background's down to it
            (:func:`~sdn3d.editing.photo.road.ray_fill`; docs/results/2026-11-30_cpu/session19/erase/).
        outline_grow: a moved car whose view turned by more than ``mask_view_deg`` (with ``silhouette='carved'``;
            else any moved car) also covers the free pixels (no object drawn or staying there) inside its box's
            projection within this share of the box's projected height of its drawn pixels, each in the colour of
            the nearest drawn one (carved as template points are): a template is not the car's outline (with the
            true pose and size a held-out car still reached past it on 4-5 % of its pixels, drawn as the road
            behind). 0 (the default): the template's pixels alone. With ground-truth geometry 0.1 gained +0.38 /
            +0.72 / +0.46 dB at 45 / 90 / 180 degrees on the seed-33 tuning turns, but on the real frame a fitted box
            larger than its car grew a blocky halo of paint around the turned car (docs/results/2026-11-28_cpu/
            session5/turns/).
        view_reflection: glass and paint drawn from the input at a new view angle take this share of the change of
            their reflection (:func:`~sdn3d.editing.photo.light.fit_reflection`, fitted per car and part on the
            input's pixels of that part seen at different angles: a window seen edge-on mirrors the sky, turned to
            face the camera it is dark); 0: the input's colours as they are.
        recolor_parts: ``recolor`` repaints the body part of the fitted mesh only (False: every pixel of the car
            whose colour is the paint's, the appearance before vehicle parts existed).
        learnt_weights: ``fill='learnt'``: the net's weights file (:func:`~sdn3d.editing.photo.learnt.load_fill_net`;
            null: the packaged ``sdn3d/resources/learnt_fill.pt``).
    """

    fill: str = "rays"
    depth_tolerance: float = 0.03
    min_view_cos: float = 0.2
    view_stretch: float = 1.5
    mask_erode_px: int | None = None
    hole_dilate_px: int = 3
    shadow_band: float = 0.12
    leftover_reach: float = 0.06
    leftover_step: float = 12.0
    contact_shadow: float = 0.3
    relight: bool = False
    inpaint_radius: int = 5
    max_level: int = 3
    unseen: str = "parts"
    part_smoothing: bool = True
    part_smoothing_crease_deg: float = 35.0
    silhouette: str = "carved"
    amodal: str = "seen"
    mask_view_deg: float = 30.0
    paste_max_iou: float = 1.0
    delete_effects: bool = False
    delete_shadow: bool = True
    recolor_parts: bool = True
    keep_in_front: bool = True
    cast_shadow: bool = False
    cast_blur: float = 1.0
    ray_blur: float = 0.0
    ray_texture: float = 0.25
    ray_span: int = 12
    ray_grain: str = "match"
    shadow_mode: str = "fill"
    shadow_light: float = 0.8
    shadow_reach: float = 0.1
    faint_light: float = 0.98
    grow_min_seen: int = 1
    grow_predicted_share: float = 0.5
    ray_marks: float = 0.2
    ray_haze: float = 1.0
    ray_haze_airlight: float = 0.25
    ray_verge: str = "edges"
    ray_vanishing: str = "telea"
    outline_grow: float = 0.0
    view_reflection: float = 1.0
    learnt_weights: str | None = None

    def __post_init__(self) -> None:
        if self.fill not in FILL_METHODS:
            raise PhotoSettingsError(f"photo.fill must be one of {FILL_METHODS}, got {self.fill!r}")
        if self.shadow_mode not in SHADOW_MODES:
            raise PhotoSettingsError(f"photo.shadow_mode must be one of {SHADOW_MODES}, got {self.shadow_mode!r}")
        if self.amodal not in AMODAL_MODES:
            raise PhotoSettingsError(f"photo.amodal must be one of {AMODAL_MODES}, got {self.amodal!r}")
        if self.silhouette not in SILHOUETTE_MODES:
            raise PhotoSettingsError(f"photo.silhouette must be one of {SILHOUETTE_MODES}, got {self.silhouette!r}")
        if self.ray_verge not in VERGE_MODES:
            raise PhotoSettingsError(f"photo.ray_verge must be one of {VERGE_MODES}, got {self.ray_verge!r}")
        if self.ray_vanishing not in VANISHING_MODES:
            raise PhotoSettingsError(
                f"photo.ray_vanishing must be one of {VANISHING_MODES}, got {self.ray_vanishing!r}")
        if self.ray_grain not in GRAIN_MODES:
            raise PhotoSettingsError(f"photo.ray_grain must be one of {GRAIN_MODES}, got {self.ray_grain!r}")
        if self.unseen not in UNSEEN_MODES:
            raise PhotoSettingsError(f"photo.unseen must be one of {UNSEEN_MODES}, got {self.unseen!r}")
        checks = (("depth_tolerance", self.depth_tolerance, 0.0, 1.0), ("shadow_band", self.shadow_band, 0.0, 1.0),
                  ("leftover_reach", self.leftover_reach, 0.0, 0.5),
                  ("leftover_step", self.leftover_step, 0.0, 100.0),
                  ("min_view_cos", self.min_view_cos, 0.0, 1.0),
                  ("contact_shadow", self.contact_shadow, 0.0, 1.0), ("cast_blur", self.cast_blur, 0.3, 16.0),
                  ("ray_blur", self.ray_blur, 0.0, 8.0), ("ray_texture", self.ray_texture, 0.0, 2.0),
                  ("ray_marks", self.ray_marks, 0.0, 1.0), ("ray_haze", self.ray_haze, 0.0, 1.0),
                  ("ray_haze_airlight", self.ray_haze_airlight, 0.0, 1.0),
                  ("shadow_light", self.shadow_light, 0.3, 1.0), ("shadow_reach", self.shadow_reach, 0.0, 0.5),
                  ("mask_view_deg", self.mask_view_deg, 0.0, 90.0),
                  ("paste_max_iou", self.paste_max_iou, 0.0, 1.0),
                  ("view_stretch", self.view_stretch, 0.0, 10.0), ("outline_grow", self.outline_grow, 0.0, 0.5),
                  ("view_reflection", self.view_reflection, 0.0, 1.0),
                  ("part_smoothing_crease_deg", self.part_smoothing_crease_deg, 1e-6, 180.0),
                  ("grow_predicted_share", self.grow_predicted_share, 0.0, 1e6))
        for name, value, lo, hi in checks:
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not lo <= float(value) <= hi:
                raise PhotoSettingsError(f"photo.{name} must be a number in [{lo}, {hi}], got {value!r}")
        faint = self.faint_light
        if isinstance(faint, bool) or not isinstance(faint, (int, float)) or not (
                faint == 0 or self.shadow_light < float(faint) <= 1.0):
            raise PhotoSettingsError(f"photo.faint_light must be 0 (none) or a number in (shadow_light "
                                     f"{self.shadow_light}, 1], got {faint!r}")
        ints = (("hole_dilate_px", self.hole_dilate_px, 0, 64), ("inpaint_radius", self.inpaint_radius, 1, 32),
                ("max_level", self.max_level, 0, 6), ("mask_erode_px", self.mask_erode_px, 0, 16),
                ("ray_span", self.ray_span, 1, 32), ("grow_min_seen", self.grow_min_seen, 0, 100000))
        for name, value, lo, hi in ints:
            if name == "mask_erode_px" and value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
                raise PhotoSettingsError(f"photo.{name} must be an integer in [{lo}, {hi}], got {value!r}")
        if self.learnt_weights is not None and (not isinstance(self.learnt_weights, str) or not self.learnt_weights):
            raise PhotoSettingsError(f"photo.learnt_weights must be a file path or null, got {self.learnt_weights!r}")
        for name in ("relight", "part_smoothing", "recolor_parts", "delete_effects", "delete_shadow", "cast_shadow",
                     "keep_in_front"):
            if not isinstance(getattr(self, name), bool):
                raise PhotoSettingsError(f"photo.{name} must be true or false, got {getattr(self, name)!r}")

    def to_dict(self) -> dict:
        return dict(self.__dict__)

    @classmethod
    def from_mapping(cls, node: Mapping | None) -> PhotoSettings:
        """Settings from a config mapping (``photo:`` of ``conf/edit.yaml`` / ``conf/bench.yaml``); unknown keys are
        refused by name."""
        values = {str(k): v for k, v in dict(node or {}).items()}
        unknown = sorted(set(values) - set(cls.__dataclass_fields__))
        if unknown:
            raise PhotoSettingsError(f"photo: unknown setting(s) {unknown}; the settings are "
                                     f"{sorted(cls.__dataclass_fields__)}")
        return cls(**values)


def source_picture(source: Tensor) -> np.ndarray:
    """``(H, W, 3)`` uint8 picture of a :attr:`PhotoResult.source` map (colours :data:`SOURCE_COLORS`)."""
    lut = np.asarray(SOURCE_COLORS, np.uint8)
    return lut[source.cpu().numpy().astype(np.int64)]


#: Colour of each part in :func:`part_picture` (sRGB uint8, by :class:`~sdn3d.meshes.parts.Part`; no part: black).
PART_COLORS = ((200, 60, 60), (80, 160, 230), (60, 60, 60), (250, 230, 120), (230, 40, 160), (240, 240, 240))


def part_picture(parts: Tensor) -> np.ndarray:
    """``(H, W, 3)`` uint8 picture of a :attr:`PhotoResult.parts` map (-1: black)."""
    lut = np.asarray(((0, 0, 0),) + PART_COLORS, np.uint8)
    return lut[parts.cpu().numpy().astype(np.int64) + 1]
