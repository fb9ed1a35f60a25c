"""The editing benchmark of 3D-SDN (Sec. 4.1, Table 1): 3D-SDN against the 2D and 2D+ baselines.

Each benchmark entry edits a source frame; its target frame shows the true result (real frames of
Virtual KITTI for the paper's file, exact re-renders for the synthetic ``vkitti_edit_benchmark.json``
written by ``sdn3d-synth``). Per entry:

1. the source scene: :func:`sdn3d.derender.derender` (``scene='derender'``: with ``proposals='semantic'``,
   3D-SDN as a user runs it, masks and semantics are the semantic branch's predictions; with ``proposals='gt'``
   they are the frame's, an *oracle*; geometry and codes come from the branches either way) or, as an
   *oracle geometry* option, :func:`~sdn3d.data.scene_gt.scene_from_frame` with codes from the texture encoder
   (``scene='oracle'``). :data:`SOURCE_LABELS` says which, in every report (:func:`source_name`);
2. the three edits of that same scene: ``3d-sdn`` (:func:`~sdn3d.editing.apply.ops_from_benchmark` +
   :func:`~sdn3d.editing.apply.apply_edits` + :func:`~sdn3d.scene.maps.scene_maps`), ``2d`` and ``2d+``
   (:func:`~sdn3d.evaluation.baselines.baseline_maps`). All three are drawn by 3D-SDN's textural generator,
   whose inputs include pose and normal maps (the baselines' come from the de-rendered geometry, moved with each
   region), unless :func:`run_benchmark` gets a ``baseline_textural`` generator: then the 2D and 2D+ edits are
   drawn by it, with texture codes from its own encoder (pooled over the source scene's regions), as the paper's
   baselines without 3D knowledge are when that generator was trained with ``use_pose=false use_normal=false``;
3. each method's picture in every mode of ``settings.compose`` (:data:`MODES`): ``photo``, the photo appearance
   (:mod:`sdn3d.editing.photo`: each edited object drawn with the source frame's own pixels through its 3D shape,
   vacated pixels inpainted; the 2D and 2D+ baselines paste the object's own pixels moved in 2D over the same fill,
   :func:`~sdn3d.evaluation.baselines.baseline_photo`; what ``sdn3d-edit`` gives a user), and the generator
   appearance's compose modes (:mod:`sdn3d.editing.compose`): ``full``, the generator's whole picture (the paper's
   protocol, Table 1), and ``edited``, the source frame with only the method's own edit region (its maps against the
   source scene's, the edited objects' footprints) redrawn and blended in, at the working size;
4. metrics against the target (:mod:`sdn3d.evaluation.image_metrics`): LPIPS (with weights), L1, SSIM, PSNR on the
   ``whole`` image, on ``all`` edited regions, on the ``largest`` one (a crop) and on the ``objects``: the target's
   visible pixels of the edited objects (the cars themselves, apart from the background fill), per mode.

Entries are also summarised by what they edit (:func:`edit_kind`: ``move``, ``rotate`` (a turn of 15 degrees or
more), ``zoom``, ``delete``, and the synthetic benchmark's ``occluder_removed``).

Edited regions come from the ground truth only, so they are the same for every method: the
benchmark's picks are resolved on the frame's ground-truth scene (:func:`~sdn3d.data.scene_gt.scene_from_frame`,
:func:`~sdn3d.editing.pick.pick_objects` by projected centre, the synthetic ``from`` point's definition; scaled
``from`` points), and an edited object's region is the
union of its visible pixels in the source and the target frames (instance maps at the working
size). ``all`` = the union over the edited objects; ``largest`` = the object with the largest
region, cropped to its box in the target frame (in the source frame when it left the view or was
deleted). Latency = de-render + edit + render of the 3D-SDN path, per entry, at the working size;
``compose`` apart: the edit region and the blend of ``compose='edited'``.

A layout diagnostic that needs no trained generator is reported too (not in the paper):
:func:`mask_iou`, the IoU between where a method draws each edited object (its composed instance
map) and where the target frame shows it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from typing import TYPE_CHECKING

import numpy as np
import torch
from torch import Tensor

from sdn3d.data.edit_benchmark import VKITTI_FRAME_SIZE, BenchmarkEntry, scale_operation
from sdn3d.data.frames import load_frame
from sdn3d.data.records import FrameRecord, load_instances
from sdn3d.data.scene_gt import frame_photo, ground_truth, scene_from_frame
from sdn3d.derender import PROPOSAL_LABELS, Models, derender, encode_scene
from sdn3d.editing.appearance import (
    PICTURE_MODES,
    Appearance,
    AppearanceRenderer,
    PictureMode,
    appearance_renderer,
    picture_mode,
    render_maps,
)
from sdn3d.editing.apply import ModifyAnchor, apply_edits, ops_from_benchmark
from sdn3d.editing.compose import (
    COMPOSE_MODES,
    Compose,
    ComposeSettings,
    ComposeSettingsError,
    compose_edit,
    edited_object_ids,
)
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.pick import PickBy, pick_objects
from sdn3d.errors import UserInputError
from sdn3d.evaluation.baselines import baseline_maps, baseline_photos
from sdn3d.evaluation.image_metrics import crop_metrics, region_image_metrics
from sdn3d.image_ops import mask_boxes, resize_map
from sdn3d.proposals import Proposals
from sdn3d.scene.code import SceneCode
from sdn3d.scene.maps import ComposedMaps, scene_maps

if TYPE_CHECKING:
    from sdn3d.geometric.fit import FitSettings
    from sdn3d.nets.lpips import LPIPS
    from sdn3d.textural.renderer import TexturalRenderer

__all__ = [
    "METHODS",
    "REGIONS",
    "COMPOSE_MODES",
    "MODES",
    "EDIT_KINDS",
    "edit_kind",
    "LAYOUT",
    "Scene",
    "SCENES",
    "PROPOSALS",
    "SOURCE_LABELS",
    "source_name",
    "BenchSettings",
    "EntryResult",
    "index_records",
    "edit_regions",
    "region_metrics",
    "mask_iou",
    "evaluate_entry",
    "run_benchmark",
    "summarize",
]

METHODS = ("3d-sdn", "2d", "2d+")
REGIONS = ("whole", "all", "largest", "objects")
#: How a method's picture is made: ``photo`` (the photo appearance), or a compose mode of the generator's picture.
MODES = PICTURE_MODES
#: What an entry edits (:func:`edit_kind`), the order of the per-kind tables.
EDIT_KINDS = ("move", "rotate", "zoom", "delete", "occluder_removed")
#: A modify that turns the object by at least this much (radians) is a ``rotate`` entry.
ROTATE_KIND_MIN = math.radians(15.0)
#: Per-method values besides the image metrics: ``metrics[method]['layout']['mask_iou']`` (:func:`mask_iou`).
LAYOUT = "layout"


class Scene(StrEnum):
    """What a pass's source scene is (module doc): ``derender``, de-rendered from the source frame (its
    ``proposals``); ``oracle``, the frame's ground-truth masks, semantics and geometry. A ``str`` equal to its value."""

    DERENDER = "derender"
    ORACLE = "oracle"


#: The scenes' names, in the order messages list them.
SCENES = tuple(s.value for s in Scene)
#: ``proposals`` of a de-rendered source scene: the semantic branch's predictions (what a user gets), or the
#: frame's ground-truth masks and semantics (an oracle).
PROPOSALS = (Proposals.SEMANTIC.value, Proposals.GT.value)
#: What a benchmark pass's source scene is made of, by :func:`source_name`; every report prints these labels.
SOURCE_LABELS = {**PROPOSAL_LABELS, "oracle": "oracle: ground-truth masks, semantics and geometry"}


@dataclass(frozen=True)
class BenchSettings:
    """How the benchmark runs.

    Attributes:
        image_size: working size ``(W, H)``.
        scene: :class:`Scene` (its name is accepted and parsed).
        proposals: :data:`PROPOSALS` of ``scene='derender'``, parsed into :class:`~sdn3d.proposals.Proposals`:
            ``semantic`` (the semantic branch's masks and semantics, 3D-SDN as a user runs it) or ``gt`` (the
            frame's: an oracle); unused by ``oracle``.
        frame_size: ``(W, H)`` of the benchmark's coordinates (1242x375).
        strict: reject ``to`` points outside the frame (False for the published file).
        pick_radius: max distance (working pixels) of a ``from`` pick; None: nearest object.
        modify_anchor: where a ``modify`` puts its object (:class:`~sdn3d.editing.apply.ModifyAnchor`; ``pick``: the
            point ``from`` lands on ``to``, as the 2D baselines paste it).
        min_pixels: visible pixels an object needs for 3D geometry in :func:`derender`.
        fit: ``scene='derender'``: the test-time fit of the proposals' vehicles (:mod:`sdn3d.proposal_fit`, a
            :class:`~sdn3d.geometric.fit.FitSettings`), what ``sdn3d-edit`` gives a user; None: the branch's poses
            as they are (the paper's protocol).
        include_identity: also evaluate the entries without operations.
        limit: evaluate at most this many entries (None: all).
        examples: entries whose pictures are kept for the example grids.
        compose: the modes evaluated (:class:`~sdn3d.editing.appearance.PictureMode`, names parsed), each reported
            apart (module doc); ``full`` is the paper's,
            ``photo`` what a user gets.
        photo: the photo appearance's settings.
        dilate_px, feather_px: the edit region's dilation and blend ramp of ``compose='edited'`` (working pixels).
    """

    image_size: tuple[int, int] = (624, 192)
    scene: Scene = Scene.DERENDER
    proposals: Proposals = Proposals.SEMANTIC
    frame_size: tuple[int, int] = VKITTI_FRAME_SIZE
    strict: bool = False
    pick_radius: float | None = None
    modify_anchor: ModifyAnchor = ModifyAnchor.PICK
    min_pixels: int = 64
    fit: FitSettings | None = None
    include_identity: bool = False
    limit: int | None = None
    examples: int = 8
    compose: tuple[PictureMode, ...] = (PictureMode.PHOTO, PictureMode.FULL, PictureMode.EDITED)
    dilate_px: int = 4
    feather_px: int = 4
    photo: PhotoSettings = field(default_factory=PhotoSettings)

    def __post_init__(self) -> None:
        if not isinstance(self.scene, str) or self.scene not in SCENES:
            raise UserInputError(f"BenchSettings.scene must be one of {SCENES}, got {self.scene!r}")
        if not isinstance(self.proposals, str) or self.proposals not in PROPOSALS:
            raise UserInputError(f"BenchSettings.proposals must be one of {PROPOSALS}, got {self.proposals!r}")
        compose = tuple(str(c) for c in self.compose)
        if not compose or len(set(compose)) != len(compose) or not set(compose) <= set(MODES):
            raise ComposeSettingsError(f"compose must list distinct modes of {MODES}, got {list(compose)}")
        anchors = tuple(a.value for a in ModifyAnchor)
        if not isinstance(self.modify_anchor, str) or self.modify_anchor not in anchors:
            raise UserInputError(f"BenchSettings.modify_anchor must be one of {anchors}, got {self.modify_anchor!r}")
        object.__setattr__(self, "scene", Scene(self.scene))
        object.__setattr__(self, "proposals", Proposals(self.proposals))
        object.__setattr__(self, "modify_anchor", ModifyAnchor(self.modify_anchor))
        object.__setattr__(self, "compose", tuple(PictureMode(c) for c in compose))
        for mode in compose:
            self.renderer(mode)  # checks the mode, dilate_px and feather_px
        object.__setattr__(self, "image_size", (int(self.image_size[0]), int(self.image_size[1])))
        object.__setattr__(self, "frame_size", (int(self.frame_size[0]), int(self.frame_size[1])))
        if self.limit is not None and self.limit < 0 or self.examples < 0:
            raise UserInputError(f"BenchSettings.limit and examples must be >= 0, got {self.limit}, {self.examples}")

    def compose_settings(self, mode: PictureMode) -> ComposeSettings:
        return ComposeSettings(mode, self.dilate_px, self.feather_px)

    def renderer(self, mode: PictureMode, textural: TexturalRenderer | None = None) -> AppearanceRenderer:
        """The appearance that draws 3D-SDN's picture in ``mode`` (:func:`~sdn3d.editing.appearance.picture_mode`)."""
        appearance, compose = picture_mode(mode, ComposeSettings(Compose.EDITED, self.dilate_px, self.feather_px))
        return appearance_renderer(appearance, photo=self.photo, compose=compose, textural=textural)

    @property
    def generator_modes(self) -> tuple[str, ...]:
        """The modes of the generator appearance."""
        return tuple(m for m in self.compose if self.renderer(m).appearance is Appearance.GENERATOR)

    @property
    def generates(self) -> bool:
        """Whether a mode draws with the generator's picture (the generator appearance, the generator fill)."""
        return any(self.renderer(m).needs_generator for m in self.compose)


def edit_kind(entry: BenchmarkEntry) -> str:
    """What ``entry`` edits (:data:`EDIT_KINDS`): its own kind when not ``'edit'``; else ``'delete'`` when it only
    deletes, ``'rotate'`` when a modify turns an object by :data:`ROTATE_KIND_MIN` or more, ``'zoom'`` when one
    changes a distance, else ``'move'``."""
    if entry.kind != "edit":
        return entry.kind
    mods = [op for op in entry.operations if op.kind == "modify"]
    if not mods:
        return "delete"
    if any(abs(op.ry) >= ROTATE_KIND_MIN for op in mods):
        return "rotate"
    if any(abs(op.zoom - 1.0) > 1e-6 for op in mods):
        return "zoom"
    return "move"


def source_name(settings: BenchSettings) -> str:
    """The key of :data:`SOURCE_LABELS` for what ``settings`` de-render the source scene from: the proposals of
    ``scene='derender'``, ``'oracle'`` for ``scene='oracle'``."""
    return Scene.ORACLE.value if settings.scene is Scene.ORACLE else settings.proposals.value


@dataclass
class EntryResult:
    """One evaluated entry.

    Attributes:
        index: entry index in the file; key: ``world/variation source->target``; operations: count.
        metrics: ``{compose: {method: {region: {metric: value}}}}`` (NaN: not computable, e.g. empty region);
            ``[compose][method]['layout']``: :func:`mask_iou` (the same in every compose mode).
        latency_ms: ``derender``, ``edit``, ``render``, ``total`` (their sum) of the 3D-SDN path, and
            ``compose`` (``compose='edited'``: edit region + blend) when evaluated.
        errors: ``{method or 'entry': message}`` for what could not be evaluated.
        images: ``{'source', 'target', '<compose>:<method>': (H, W, 3) uint8}`` for example entries, else None.
        regions: ``(H, W)`` bool union of edited regions (example entries only).
        kind: the entry's :data:`~sdn3d.data.edit_benchmark.ENTRY_KINDS` (``'edit'``; ``'occluder_removed'``
            entries are summarised apart); edit_kind: :func:`edit_kind`.
        cars: the cars the entry edits, ``world/instance id`` of each ground-truth car its operations pick (the
            same car in every frame and variation of its world; ground truth used only to group the entries of one
            car for the paired intervals, ``sdn3d.cli.bench.edited_car_groups``); empty where none was found.
    """

    index: int
    key: str
    operations: int
    metrics: dict[str, dict[str, dict[str, float]]] = field(default_factory=dict)
    latency_ms: dict[str, float] = field(default_factory=dict)
    errors: dict[str, str] = field(default_factory=dict)
    images: dict[str, np.ndarray] | None = None
    regions: np.ndarray | None = None
    kind: str = "edit"
    edit_kind: str | None = None
    cars: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.edit_kind is None:  # :func:`edit_kind` of the entry; unknown: its kind
            self.edit_kind = self.kind

    def to_json(self) -> dict:
        return {"index": self.index, "key": self.key, "kind": self.kind, "edit_kind": self.edit_kind,
                "operations": self.operations, "cars": list(self.cars),
                "metrics": self.metrics,
                "latency_ms": self.latency_ms, "errors": self.errors}


def index_records(records: Sequence[FrameRecord]) -> dict[tuple[str, str, int], FrameRecord]:
    """``{(world, variation, frame): record}`` (the benchmark names frames that way)."""
    return {(r.world, r.variation, int(r.frame)): r for r in records}


def _instances(record: FrameRecord, size: tuple[int, int]) -> Tensor:
    if record.instance_path is None:
        raise ValueError(f"{record.key} has no instance map: edited regions need one")
    return resize_map(torch.from_numpy(load_instances(record)).long(), size)


def edit_regions(entry: BenchmarkEntry, source: FrameRecord, target: FrameRecord, image_size: tuple[int, int],
                 frame_size: tuple[int, int] = VKITTI_FRAME_SIZE) -> tuple[Tensor, Tensor, list[int]]:
    """Ground-truth edited regions of ``entry`` (module doc).

    Returns:
        ``all (H, W)`` bool, ``largest_box (4,)`` half-open ``(x0, y0, x1, y1)`` and the edited
        objects' instance ids.
    """
    oracle = scene_from_frame(source, image_size)
    ops = [scale_operation(op, frame_size, image_size) for op in entry.operations]
    ids = pick_objects(oracle, [op.from_uv for op in ops], [op.kind == "modify" for op in ops], by=PickBy.CENTRE)
    src, tgt = _instances(source, image_size), _instances(target, image_size)
    id_t = torch.tensor(ids, dtype=torch.long)
    regions = (src[None] == id_t[:, None, None]) | (tgt[None] == id_t[:, None, None])  # (K, H, W)
    area = regions.flatten(1).sum(1)
    k = int(area.argmax()) if len(ids) else 0
    in_target = tgt == (ids[k] if ids else -1)
    box = mask_boxes((in_target if bool(in_target.any()) else regions[k] if len(ids) else in_target)[None])[0]
    return regions.any(0) if len(ids) else torch.zeros_like(src, dtype=torch.bool), box, ids


def region_metrics(pred: Tensor, target: Tensor, regions: Tensor, box: Tensor,
                   lpips_net: LPIPS | None = None, objects: Tensor | None = None) -> dict[str, dict[str, float]]:
    """``{region: {metric: value}}`` of ``pred`` vs ``target`` ``(3, H, W)`` (module doc); ``objects (H, W)``: the
    target's visible pixels of the edited objects (None: that region is left out)."""
    p, t = pred[None].float().cpu(), target[None].float().cpu()
    net = lpips_net.cpu() if lpips_net is not None else None
    masks = {"whole": None, "all": regions[None]} | ({"objects": objects[None]} if objects is not None else {})
    out = region_image_metrics(p, t, masks, net)  # one SSIM map for the three regions
    out = {"whole": out["whole"], "all": out["all"], "largest": crop_metrics(p, t, box[None].float(), net)} | (
        {"objects": out["objects"]} if objects is not None else {})
    return {region: {k: float(v[0]) for k, v in values.items()} for region, values in out.items()}


def mask_iou(instances: Tensor, target: Tensor, picked: Sequence[int], truth: Sequence[int]) -> float:
    """Mean IoU over a benchmark entry's operations between where a method draws the object it picked for an
    operation (``picked``: ids of its own source scene, one per operation) and where the target frame ``(H, W)``
    shows the object the operation meant (``truth``: ground-truth ids, same order; :func:`edit_regions`).

    A geometry diagnostic (not in the paper): where the edit puts each object, independent of the texture.
    With predicted proposals the scene's ids are the semantic branch's own, so pairs, not ids, are compared.
    Pairs absent from both maps (deleted) are skipped; NaN when none is left.
    """
    if len(picked) != len(truth):
        raise ValueError(f"picked and truth must pair up, got {len(picked)} and {len(truth)} ids")
    if not len(picked):
        return float("nan")
    pred = instances[None] == torch.tensor(list(picked), dtype=torch.long)[:, None, None]
    true = target[None] == torch.tensor(list(truth), dtype=torch.long)[:, None, None]
    union = (pred | true).flatten(1).sum(1)
    inter = (pred & true).flatten(1).sum(1)
    keep = union > 0
    return float((inter[keep] / union[keep]).mean()) if bool(keep.any()) else float("nan")


def _sync(models: Models) -> None:
    if models.textural is not None and models.textural.device.type == "cuda":
        torch.cuda.synchronize(models.textural.device)


def _source_scene(image: Tensor, intrinsics, record: FrameRecord, models: Models,
                  settings: BenchSettings) -> SceneCode:
    if settings.scene is Scene.ORACLE:
        scene = scene_from_frame(record, settings.image_size, models.textural.spec.code_dim)
        return encode_scene(scene, image, models.textural)
    gt = ground_truth(record, (intrinsics.width, intrinsics.height))
    return derender(image, intrinsics, models, settings.proposals, gt, min_pixels=settings.min_pixels,
                    fit=settings.fit, photo=frame_photo(record, (intrinsics.width, intrinsics.height)))


def _to_uint8(image: Tensor) -> np.ndarray:
    return (image.detach().cpu().clamp(0, 1).permute(1, 2, 0).numpy() * 255 + 0.5).astype(np.uint8)


def _method_pictures(entry: BenchmarkEntry, scene: SceneCode, baseline: tuple[SceneCode, TexturalRenderer],
                     models: Models, settings: BenchSettings, result: EntryResult, derender_ms: float
                     ) -> tuple[dict[str, Tensor], dict[str, ComposedMaps], Tensor, dict[str, list[int]],
                                SceneCode | None]:
    """``({method: (3, H, W) generator picture}, {method: maps}, edited ids (K,), {method: picked ids, one per
    operation}, 3D-SDN's edited scene)`` of every method that could draw the entry (a method's :class:`ValueError`
    goes to ``result.errors``); the generator pictures only when a generator mode is evaluated. Sets the 3D-SDN
    path's latency. ``baseline``: the source scene (its codes from that generator's encoder) and the generator of
    the 2D and 2D+ edits."""
    t1 = time.perf_counter()
    generate = settings.generates
    images: dict[str, Tensor] = {}
    maps: dict[str, ComposedMaps] = {}
    picks: dict[str, list[int]] = {}
    ids = torch.zeros(0, dtype=torch.long)
    edited = None
    try:
        ops = ops_from_benchmark(entry, scene, settings.frame_size, settings.strict, settings.pick_radius,
                                 settings.modify_anchor)
        picks["3d-sdn"] = [op.instance_id for op in ops]
        edited = apply_edits(scene, ops)
        t2 = time.perf_counter()
        maps["3d-sdn"] = scene_maps(edited, num_bins=models.textural.spec.pose_bins)
        if generate:
            images["3d-sdn"] = render_maps(maps["3d-sdn"], models.textural)
        _sync(models)
        t3 = time.perf_counter()
        result.latency_ms = {"derender": derender_ms, "edit": 1000 * (t2 - t1), "render": 1000 * (t3 - t2),
                             "total": derender_ms + 1000 * (t3 - t1)}
        ids = edited_object_ids(scene.objects, edited.objects)
    except ValueError as exc:
        result.errors["3d-sdn"] = str(exc)
    baseline_scene, baseline_textural = baseline
    points = [scale_operation(op, settings.frame_size, settings.image_size).from_uv for op in entry.operations]
    picked_2d: list[int] | None = None  # the same scene and points for 2D and 2D+: one pick (it composes the scene)
    for mode in ("2d", "2d+"):
        try:
            if picked_2d is None:
                picked_2d = pick_objects(baseline_scene, points, None, settings.pick_radius)  # as baseline_maps
            picks[mode] = picked_2d
            maps[mode] = baseline_maps(baseline_scene, entry, mode, settings.frame_size,
                                       max_distance=settings.pick_radius)
            if generate:
                images[mode] = render_maps(maps[mode], baseline_textural)
        except ValueError as exc:
            result.errors[mode] = str(exc)
    return images, maps, ids, picks, edited


def _composed(images: dict[str, Tensor], maps: dict[str, ComposedMaps], source: Tensor, scene: SceneCode,
              baseline_scene: SceneCode, ids: Tensor, models: Models, settings: BenchSettings, result: EntryResult,
              entry: BenchmarkEntry, edited: SceneCode | None) -> dict[str, dict[str, Tensor]]:
    """``{mode: {method: (3, H, W)}}``: every method's picture in every mode (working size; the source frame is
    the original); times the 3D-SDN path's ``photo`` and ``compose='edited'`` steps. Each method's edit region is
    against the source scene it edited (``baseline_scene`` for 2D and 2D+: its own codes)."""
    identity = PixelFrame(settings.image_size, settings.image_size)
    bins = models.textural.spec.pose_bins
    state = None  # 3D-SDN's source state, shared by its appearances (its source maps made once)
    before: dict[str, ComposedMaps | None] = dict.fromkeys(METHODS)
    if PictureMode.EDITED in settings.compose:
        state = appearance_renderer(Appearance.GENERATOR).prepare(source, identity, scene)
        before["3d-sdn"] = state.source_maps(bins)
        before["2d"] = before["2d+"] = before["3d-sdn"] if baseline_scene is scene else scene_maps(baseline_scene)
    out: dict[str, dict[str, Tensor]] = {}
    for mode in settings.compose:
        out[mode] = {}
        renderer = settings.renderer(mode, models.textural)
        photo = renderer.appearance is Appearance.PHOTO
        if state is None:
            state = renderer.prepare(source, identity, scene)
        if edited is not None and (photo or "3d-sdn" in images):
            generated = (maps["3d-sdn"], images["3d-sdn"]) if "3d-sdn" in images else None
            t0 = time.perf_counter()
            # (benchmark ops name no colour: nothing to repaint)
            out[mode]["3d-sdn"] = renderer.draw(state, edited, (), generated).image
            key = "photo" if photo else "compose" if mode is PictureMode.EDITED else None
            if key and result.latency_ms:
                result.latency_ms[key] = 1000 * (time.perf_counter() - t0)
        if photo:  # the baselines paste the same scene's objects the generator path edits (one removal for both)
            modes = [method for method in ("2d", "2d+") if method in maps]
            out[mode] |= baseline_photos(source, scene, entry, modes, settings.frame_size, settings.photo,
                                         max_distance=settings.pick_radius, fills={m: images.get(m) for m in modes})
            continue
        for method, picture in images.items():  # the 2D baselines: label maps, no scene to hand an appearance
            if method != "3d-sdn":
                out[mode][method], _ = compose_edit(settings.compose_settings(mode), picture, source, identity,
                                                    before[method], maps[method], ids)
    return out


def evaluate_entry(index: int, entry: BenchmarkEntry, source: FrameRecord, target: FrameRecord, models: Models,
                   settings: BenchSettings, lpips_net: LPIPS | None = None, keep_images: bool = False,
                   baseline_textural: TexturalRenderer | None = None) -> EntryResult:
    """Evaluate one entry with every method in every compose mode (a method's :class:`ValueError` is recorded,
    not raised). ``baseline_textural``: the generator of the 2D and 2D+ edits (module doc); None: 3D-SDN's."""
    result = EntryResult(index, f"{entry.world}/{entry.variation} {entry.source_frame:05d}->{entry.target_frame:05d}",
                         len(entry.operations), kind=entry.kind, edit_kind=edit_kind(entry))
    size = settings.image_size
    src = load_frame(source, size, semantic=False, instances=False)
    tgt = load_frame(target, size, semantic=False, instances=False).image
    regions, box, gt_ids = edit_regions(entry, source, target, size, settings.frame_size)
    result.cars = tuple(f"{entry.world}/{i}" for i in sorted(set(gt_ids)))
    target_instances = _instances(target, size)
    _sync(models)
    t0 = time.perf_counter()
    scene = _source_scene(src.image, src.intrinsics, source, models, settings)
    _sync(models)
    derender_ms = 1000 * (time.perf_counter() - t0)
    baseline_scene = scene if baseline_textural is None else encode_scene(scene, src.image, baseline_textural)
    baseline = (baseline_scene, baseline_textural or models.textural)
    images, maps, ids, picks, edited = _method_pictures(entry, scene, baseline, models, settings, result,
                                                        derender_ms)
    composed = _composed(images, maps, src.image, scene, baseline_scene, ids, models, settings, result, entry, edited)
    layout = {m: {"mask_iou": mask_iou(maps[m].instance.cpu(), target_instances, picks[m], gt_ids)} for m in maps}
    objects = torch.isin(target_instances, torch.tensor(gt_ids, dtype=torch.long))
    for mode, pictures in composed.items():
        result.metrics[mode] = {m: region_metrics(pictures[m], tgt, regions, box, lpips_net, objects)
                                | {LAYOUT: layout[m]} for m in METHODS if m in pictures}
    if keep_images:
        result.images = {"source": _to_uint8(src.image), "target": _to_uint8(tgt)}
        result.images |= {f"{mode}:{m}": _to_uint8(img) for mode, pictures in composed.items()
                          for m, img in pictures.items()}
        result.regions = regions.numpy()
    return result


def run_benchmark(entries: Sequence[BenchmarkEntry], records: Mapping[tuple[str, str, int], FrameRecord],
                  models: Models, settings: BenchSettings, lpips_net: LPIPS | None = None,
                  progress: Callable[[int, int, EntryResult], None] | None = None,
                  baseline_textural: TexturalRenderer | None = None) -> list[EntryResult]:
    """Evaluate ``entries`` (identity ones only with ``include_identity``); frames from ``records``.
    ``baseline_textural``: the generator of the 2D and 2D+ edits (module doc); None: 3D-SDN's (``models``).

    Raises:
        ValueError: no textural model, or not a single entry whose frames exist in ``records``.
    """
    if models.textural is None:
        raise ValueError("the benchmark renders every method with the textural branch: models.textural is None")
    chosen = [(i, e) for i, e in enumerate(entries) if settings.include_identity or not e.is_identity]
    if settings.limit is not None:
        chosen = chosen[: settings.limit]
    results: list[EntryResult] = []
    found = 0
    for n, (i, entry) in enumerate(chosen):
        pair = [records.get((entry.world, entry.variation, f)) for f in (entry.source_frame, entry.target_frame)]
        if None in pair:
            which = "source" if pair[0] is None else "target"
            frame = entry.source_frame if pair[0] is None else entry.target_frame
            result = EntryResult(i, f"{entry.world}/{entry.variation} {entry.source_frame:05d}->"
                                    f"{entry.target_frame:05d}", len(entry.operations), kind=entry.kind,
                                 edit_kind=edit_kind(entry),
                                 errors={"entry": f"{which} frame {entry.world}/{entry.variation}/{frame:05d} "
                                                  "not in the dataset"})
        else:
            found += 1
            try:
                result = evaluate_entry(i, entry, pair[0], pair[1], models, settings, lpips_net,
                                        keep_images=found <= settings.examples, baseline_textural=baseline_textural)
            except ValueError as exc:  # e.g. no object to pick: the entry is reported, the run goes on
                result = EntryResult(i, f"{entry.world}/{entry.variation} {entry.source_frame:05d}->"
                                        f"{entry.target_frame:05d}", len(entry.operations), kind=entry.kind,
                                 edit_kind=edit_kind(entry),
                                     errors={"entry": str(exc)})
        results.append(result)
        if progress is not None:
            progress(n + 1, len(chosen), result)
    if chosen and not found:
        first = chosen[0][1]
        raise UserInputError(f"none of the {len(chosen)} benchmark entries has its frames in the dataset "
                             f"(first: {first.world}/{first.variation} frame {first.source_frame}); "
                             "is data.root the benchmark's dataset?")
    return results


def _stats(values: list[float]) -> dict[str, float | int]:
    finite = [v for v in values if math.isfinite(v)]
    if not finite:
        return {"mean": float("nan"), "n": 0}
    return {"mean": float(np.mean(finite)), "median": float(np.median(finite)), "n": len(finite)}


def summarize(results: Sequence[EntryResult]) -> dict:
    """Means over the ``'edit'`` entries (the paper's Table 1): ``{'methods': {compose: {method: {region: {metric:
    {mean, median, n}}}}}, 'latency_ms': {...}, 'entries', 'evaluated', 'failed': {method: count}}`` (non-finite
    values, e.g. empty regions, are skipped), plus ``'by_kind': {kind: the same over that kind's entries}`` for every
    :data:`EDIT_KINDS` present (:func:`edit_kind`: the paper's edits split into move, rotate, zoom and delete, and
    the synthetic benchmark's ``'occluder_removed'``, which the overall means leave out)."""
    edits = [r for r in results if r.kind == "edit"]
    out = _summary(edits)
    present = set(r.edit_kind for r in results)
    out["by_kind"] = {kind: _summary([r for r in results if r.edit_kind == kind]) for kind in EDIT_KINDS
                      if kind in present}
    return out


def _summary(results: Sequence[EntryResult]) -> dict:
    modes = list(dict.fromkeys(c for r in results for c in r.metrics))  # in the order evaluated
    methods: dict = {}
    for mode in modes:
        methods[mode] = {}
        for method in METHODS:
            rows = [r.metrics[mode][method] for r in results if method in r.metrics.get(mode, {})]
            methods[mode][method] = {region: {k: _stats([row.get(region, {}).get(k, math.nan) for row in rows])
                                              for k in sorted({k for row in rows for k in row.get(region, {})})}
                                     for region in (*REGIONS, LAYOUT)}
    latency = {k: _stats([r.latency_ms[k] for r in results if k in r.latency_ms])
               for k in ("derender", "edit", "render", "total", "compose", "photo")}
    failed = {m: sum(1 for r in results if m in r.errors or "entry" in r.errors) for m in METHODS}
    return {"entries": len(results), "evaluated": sum(1 for r in results if r.metrics), "failed": failed,
            "compose": modes, "methods": methods, "latency_ms": latency}
