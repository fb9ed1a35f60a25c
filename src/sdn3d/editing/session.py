"""One image edited many times: the models loaded once, the image de-rendered once, any list of ops applied and drawn.

``sdn3d-edit`` (one call: one de-render, one edit) and ``sdn3d-app`` (one de-render per image and set of boxes, an
edit per interaction) both go through :class:`EditSession`, so a spec the app shows reproduces its picture through
``sdn3d-edit`` bit for bit: the same de-render, the same :func:`~sdn3d.editing.spec.resolve_ops` /
:func:`~sdn3d.editing.spec.apply_spec`, the same drawing (the appearance of the settings,
:func:`~sdn3d.editing.appearance.appearance_renderer`, its source state kept with the de-rendered scene).

The stages::

    EditInput (working image, camera, PixelFrame, the input's own pixels, optional oracle GroundTruth)
      --EditSession.derender(input, spec)-->  Derendered (SceneCode + box records; cached per image and boxes)
      --EditSession.edit(derendered, spec)--> EditResult (resolved ops, edited scene, edited picture at the input's
                                                           resolution, timings, warnings; .record(): edit.json)

The session never reads a dataset: whoever opens a dataset frame passes its pixels and (for an oracle) its
:class:`~sdn3d.derender.GroundTruth` in the :class:`EditInput`.
"""

from __future__ import annotations

import dataclasses
import threading
import time
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import torch
from torch import Tensor

import sdn3d.derender as derendering
from sdn3d.derender import PROPOSAL_LABELS, GroundTruth, Models, Proposals
from sdn3d.editing.appearance import (
    APPEARANCES,
    Appearance,
    AppearanceRenderer,
    Drawn,
    SourceState,
    appearance_renderer,
    generate,
)
from sdn3d.editing.compose import ComposeSettings, edited_object_ids
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import EditOp, SetBackgroundCode, SetCode
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.spec import EditSpec, EditSpecError, apply_spec, box_prompts, resolve_ops
from sdn3d.errors import InputError
from sdn3d.image_ops import InputPhoto
from sdn3d.math3d.camera import Intrinsics
from sdn3d.scene.code import SceneCode
from sdn3d.textural.codes import CodeBank

__all__ = ["EditInput", "SessionSettings", "Derendered", "EditResult", "EditSession", "boxes_record",
           "fit_warnings", "refuse_boxes", "BoxRefusedError", "object_origins", "proposals_record", "op_record",
           "to_uint8"]


def to_uint8(image: Tensor) -> np.ndarray:
    """``(3, H, W)`` float in [0, 1] -> ``(H, W, 3)`` uint8 (rounded)."""
    return (image.detach().cpu().clamp(0, 1).permute(1, 2, 0).numpy() * 255 + 0.5).astype(np.uint8)


@dataclass(frozen=True, eq=False)
class EditInput:
    """An image ready to de-render.

    Attributes:
        image: ``(3, h, w)`` float in [0, 1] at the working size.
        intrinsics: the working image's camera.
        frame: how the input's pixels became the working image's (the spec's pixels are the input's).
        picture: ``(H, W, 3)`` uint8, the input at its own resolution (what the photo appearance draws with).
        name: what edit.json calls the input (the file, or the dataset frame's key).
        key: identifies the input in the session's de-render cache (two inputs with one key are one image).
        ground_truth: the dataset frame's ground truth at the working size (``proposals`` gt / auto), or None.
    """

    image: Tensor
    intrinsics: Intrinsics
    frame: PixelFrame
    picture: np.ndarray
    name: str
    key: str
    ground_truth: GroundTruth | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "picture", np.ascontiguousarray(self.picture))  # one buffer: the photo state binds
        h_in, w_in = self.picture.shape[:2]
        if self.picture.dtype != np.uint8 or self.picture.ndim != 3 or (w_in, h_in) != tuple(self.frame.input_size):
            raise ValueError(f"EditInput.picture must be (H, W, 3) uint8 of the frame's input size "
                             f"{tuple(self.frame.input_size)}, got {self.picture.shape} {self.picture.dtype}")
        if tuple(self.image.shape[1:]) != (self.intrinsics.height, self.intrinsics.width):
            raise ValueError(f"EditInput.image {tuple(self.image.shape)} is not of the intrinsics' size "
                             f"{self.intrinsics.width}x{self.intrinsics.height}")

    @property
    def input_size(self) -> tuple[int, int]:
        """``(W, H)`` of the input image."""
        return int(self.picture.shape[1]), int(self.picture.shape[0])

    @property
    def original(self) -> Tensor:
        """``(3, H, W)`` uint8 view of :attr:`picture` (no copy)."""
        return torch.from_numpy(self.picture).permute(2, 0, 1)

    @property
    def photo(self) -> InputPhoto:
        """The input at its own resolution with :attr:`frame`'s map: the geometric branch's crops are read from it
        (:func:`sdn3d.derender.derender`'s ``photo``)."""
        return self.frame.photo(self.original.float().div(255.0))


@dataclass(frozen=True)
class SessionSettings:
    """Everything that decides what an edit looks like (``conf/edit.yaml``'s keys of the same names).

    Attributes:
        proposals: where the objects come from (:class:`sdn3d.proposals.Proposals`; a name is parsed).
        min_pixels: visible pixels (working size) an object needs for 3D geometry (``geometric.min_pixels``).
        refine: the Cityscapes test-time fit of the geometry, or None (off).
        fit_proposals: the proposals' vehicles get the box objects' test-time fit (``box_fit``;
            :mod:`sdn3d.proposal_fit`); False: the geometric branch's poses as they are.
        box_fit: the 3D fit of objects named by a box (:class:`~sdn3d.geometric.fit.FitSettings`; None: defaults).
        box_prior: seed GrabCut with the semantic branch's vehicle probability.
        box_iterations: GrabCut iterations per box.
        box_refine_masks: GrabCut once more, seeded by each well-fitted box object's 3D shape.
        pick_radius: pixels (working size) a pick by position may be from an object's projected centre (None: any).
        strict: benchmark points must lie inside the frame.
        seed: randomness of ``recolor: sample``.
        appearance: :class:`~sdn3d.editing.appearance.Appearance` (a name is parsed).
        photo: the photo appearance's settings.
        compose: how the generator's picture is composed into the input (appearance=generator).
        diagnostics: also the unedited scene's picture and both scenes' maps (a second generator pass).
    """

    proposals: str = "semantic"
    min_pixels: int = 64
    refine: Any = None
    fit_proposals: bool = True
    box_fit: Any = None
    box_prior: bool = False
    box_iterations: int = 5
    box_refine_masks: bool = True
    pick_radius: float | None = 16.0
    strict: bool = True
    seed: int = 0
    appearance: Appearance = Appearance.PHOTO
    photo: PhotoSettings = field(default_factory=PhotoSettings)
    compose: ComposeSettings = field(default_factory=ComposeSettings)
    diagnostics: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "proposals", Proposals.parse(self.proposals, InputError))
        if self.appearance not in APPEARANCES:
            raise InputError(f"appearance must be one of {list(APPEARANCES)} (photo: each edited car drawn with its "
                             f"own pixels through its 3D shape; generator: the paper's textural generator), got "
                             f"{self.appearance!r}")
        object.__setattr__(self, "appearance", Appearance(self.appearance))

    @property
    def generates(self) -> bool:
        """Whether an edit runs the generator (its appearance, the generator fill, or the diagnostics)."""
        return appearance_renderer(self.appearance, photo=self.photo, compose=self.compose).needs_generator \
            or self.diagnostics


@dataclass(frozen=True)
class Derendered:
    """An input de-rendered with a set of box objects.

    Attributes:
        input: what was de-rendered.
        scene: the de-rendered scene (working size).
        boxes: per object named by a box, ``scene.meta['boxes']``'s record with ``input_box`` (input pixels).
        warnings: poor or missing 3D fits of box objects (:func:`fit_warnings`).
        derender_ms: the de-render's wall time.
        source: what the appearance computed from this scene alone, kept for its next edit
            (:class:`~sdn3d.editing.appearance.SourceState`: the pictures are the same bit for bit).
    """

    input: EditInput
    scene: SceneCode
    boxes: list[dict]
    warnings: list[str]
    derender_ms: float
    source: SourceState | None = field(default=None, repr=False)


@dataclass
class EditResult:
    """One edit of a :class:`Derendered` scene.

    Attributes:
        derendered: the scene it started from.
        ops: the spec's ops resolved against it.
        edited_scene: the scene after them.
        edited: ``(H, W, 3)`` uint8, the edited picture at the input's resolution (``compose=full``: the
            generator's picture at the working size).
        region: ``(h, w)`` bool pixels taken from the generator (compose=edited), else None.
        source_map: ``(H, W)`` uint8 where each pixel came from (appearance=photo), else None.
        compose: edit.json's ``compose`` record; photo: its ``photo`` record (appearance=photo), else None.
        generated: ``(3, h, w)`` the generator's edited picture, or None (not run).
        reconstruction: ``(3, h, w)`` the generator's unedited picture (diagnostics), or None.
        source_maps, edited_maps: both scenes' :class:`~sdn3d.scene.maps.SceneMaps` where drawn, else None.
        times: wall times in ms (``derender_ms``, ``edit_ms``, ``render_ms``, ``photo_ms``, ``compose_ms``).
        warnings: what the drawing warned about (the de-render's are in ``derendered.warnings``).
    """

    derendered: Derendered
    ops: list[EditOp]
    edited_scene: SceneCode
    edited: np.ndarray
    region: Tensor | None
    source_map: Tensor | None
    compose: dict
    photo: dict | None
    generated: Tensor | None
    reconstruction: Tensor | None
    source_maps: Any
    edited_maps: Any
    times: dict[str, float]
    warnings: list[str]

    @property
    def scene(self) -> SceneCode:
        return self.derendered.scene

    def record(self, appearance: str) -> dict:
        """edit.json's account of the edit (the caller adds what it knows: input, edits, checkpoints, config)."""
        scene, edited = self.scene, self.edited_scene
        out = {"image_size": list(scene.image_size), "intrinsics": scene.intrinsics.to_dict(),
               "ops": [op_record(op) for op in self.ops],
               "objects": {"source": scene.objects.instance_id.tolist(), "edited": edited.objects.instance_id.tolist(),
                           "with_geometry": scene.objects.instance_id[scene.objects.has_geometry].tolist()},
               "timings_ms": dict(self.times), "proposals": proposals_record(scene), "appearance": appearance,
               "compose": self.compose}
        if self.photo is not None:
            out["photo"] = self.photo
        out["refined"] = bool(scene.meta.get("refined", False))  # the Cityscapes test-time fit (refine.enabled)
        out["edited_objects"] = object_origins(scene, edited_object_ids(scene.objects, edited.objects),
                                               self.derendered.boxes)
        if self.derendered.boxes:
            out["boxes"] = self.derendered.boxes
        out["input_transform"] = self.derendered.input.frame.to_dict()
        out["warnings"] = self.derendered.warnings + self.warnings
        return out


def op_record(op: EditOp) -> dict:
    """An op as edit.json lists it (``{'op': 'Move', 'instance_id': ..., ...}``)."""
    return {"op": type(op).__name__, **{k: list(v) if isinstance(v, tuple) else v
                                        for k, v in dataclasses.asdict(op).items()}}


class EditSession:
    """The models, loaded once, and the de-rendered scenes of the images opened (the last ``cache_size``).

    Args:
        models: the branches (:class:`~sdn3d.derender.Models`; ``textural`` is needed to encode and draw).
        code_bank: training codes for ``recolor`` by ``sample`` / ``color`` (None: none).
        settings: :class:`SessionSettings`.
        cache_size: de-rendered (image, boxes) pairs kept; the oldest is dropped first.

    Calls may come from several threads (a server): the networks run one call at a time (``lock``).

    Example (``sdn3d-edit`` does this once; ``sdn3d-app`` derenders once and edits per interaction)::

        session = EditSession(models, code_bank, settings)
        scene = session.derender(edit_input, spec)
        result = session.edit(scene, spec)          # result.edited: (H, W, 3) uint8 at the input's size
    """

    def __init__(self, models: Models, code_bank: CodeBank | None = None,
                 settings: SessionSettings | None = None, cache_size: int = 8) -> None:
        if models.textural is None:
            raise InputError("checkpoints.textural is required (the generator renders the result; or give "
                             "run=<training output directory>)")
        self.models = models
        self.code_bank = code_bank
        self.settings = settings or SessionSettings()
        self.cache_size = int(cache_size)
        self.lock = threading.RLock()
        s = self.settings
        self.renderer: AppearanceRenderer = appearance_renderer(s.appearance, photo=s.photo, compose=s.compose,
                                                                textural=models.textural)
        self._scenes: OrderedDict[tuple, Derendered] = OrderedDict()

    def derender(self, inp: EditInput, spec: EditSpec | None = None) -> Derendered:
        """``inp`` de-rendered with ``spec``'s objects named by a box (none: ``spec`` None or without ``objects``);
        the same image and boxes again: the cached scene.

        Raises:
            EditSpecError: a box outside the working image; UserInputError: ``proposals=boxes`` without boxes, a
                missing branch, a class that is not an object class.
        """
        s = self.settings
        boxes = None
        if spec is not None and spec.objects:
            boxes = box_prompts(spec, (inp.intrinsics.width, inp.intrinsics.height), inp.frame, fit=s.box_fit,
                                prior=s.box_prior, iterations=s.box_iterations, refine_masks=s.box_refine_masks)
        key = (inp.key, None if boxes is None else (tuple(boxes.boxes.flatten().tolist()), boxes.classes))
        with self.lock:
            hit = self._scenes.get(key)
            if hit is not None and hit.input is inp:
                self._scenes.move_to_end(key)
                refuse_boxes(spec, hit, s.box_fit)
                return hit
            t0 = time.perf_counter()
            # through the module: a test may stand in for the de-render (sdn3d.derender.derender)
            scene = derendering.derender(inp.image, inp.intrinsics, self.models, s.proposals, inp.ground_truth,
                                         min_pixels=s.min_pixels, refine=s.refine, boxes=boxes,
                                         fit=self.proposal_fit, photo=inp.photo)
            scene.meta["refined"] = s.refine is not None
            elapsed = 1000 * (time.perf_counter() - t0)
            records = boxes_record(scene, inp.frame)
            poor = scene.meta.get("fit", {}).get("poor_iou")
            done = Derendered(inp, scene, records, fit_warnings(records, poor), elapsed,
                              self.renderer.prepare(inp.original, inp.frame, scene))
            self._scenes[key] = done
            while len(self._scenes) > self.cache_size:
                self._scenes.popitem(last=False)
            refuse_boxes(spec, done, s.box_fit)  # after caching: the same boxes with force: true cost nothing more
            return done

    @property
    def proposal_fit(self) -> Any:
        """The :class:`~sdn3d.geometric.fit.FitSettings` of the proposals' test-time fit, or None (off)."""
        from sdn3d.geometric.fit import FitSettings

        s = self.settings
        return (s.box_fit or FitSettings()) if s.fit_proposals else None

    def forget(self, key_prefix: str) -> None:
        """Drop the cached scenes of every input whose key starts with ``key_prefix`` (a closed app session)."""
        with self.lock:
            for key in [k for k in self._scenes if str(k[0]).startswith(key_prefix)]:
                del self._scenes[key]

    def resolve(self, derendered: Derendered, spec: EditSpec) -> tuple[list[EditOp], SceneCode]:
        """``(ops, edited scene)``: ``spec`` checked against the scene (:func:`~sdn3d.editing.spec.resolve_ops`) and
        applied (:func:`~sdn3d.editing.spec.apply_spec`); nothing drawn.

        Raises:
            EditError: naming the op (no such object, a target outside the frame, an object without geometry, ...).
        """
        s = self.settings
        generator = torch.Generator().manual_seed(int(s.seed))
        ops = resolve_ops(spec, derendered.scene, self.code_bank, s.pick_radius, strict=s.strict, generator=generator,
                          frame=derendered.input.frame)
        self.renderer.check(spec, self.code_bank)
        return ops, apply_spec(derendered.scene, ops, spec)

    def edit(self, derendered: Derendered, spec: EditSpec) -> EditResult:
        """Apply ``spec``'s ops to ``derendered``'s scene and draw the result (module doc).

        Raises:
            EditError / EditSpecError: naming the op; PhotoSettingsError: a photo setting the scene cannot honour.
        """
        times = {"derender_ms": derendered.derender_ms}
        with self.lock:
            t0 = time.perf_counter()
            ops, edited_scene = self.resolve(derendered, spec)
            times["edit_ms"] = 1000 * (time.perf_counter() - t0)
            drawn = self._draw(derendered, edited_scene, ops, times)
        return EditResult(derendered, ops, edited_scene, times=times, **drawn)

    def _draw(self, derendered: Derendered, edited_scene: SceneCode, ops: list[EditOp],
              times: dict[str, float]) -> dict[str, Any]:
        """The appearance's picture of ``edited_scene`` (timed: ``render_ms`` the generator, ``photo_ms`` /
        ``compose_ms``) and what :class:`EditResult` shows besides: both scenes' maps where the generator ran and
        (diagnostics) the unedited scene's picture."""
        s = self.settings
        state = derendered.source
        if state is None or state.scene is not derendered.scene:
            raise ValueError("EditSession.edit: the de-rendered scene has no source state of its own (derender it)")
        generated = None
        if s.diagnostics:  # the generator's picture besides the appearance's (the photo appearance draws none)
            t0 = time.perf_counter()
            generated = generate(edited_scene, self.models.textural)
            times["render_ms"] = 1000 * (time.perf_counter() - t0)
        drawn = self.renderer.draw(state, edited_scene, ops, generated)
        times |= drawn.times
        out = {"generated": drawn.generated, "reconstruction": None, "source_maps": None, "edited_maps": drawn.maps}
        if s.generates:
            bins = self.models.textural.spec.pose_bins
            out["source_maps"] = state.source_maps(bins)
            if s.diagnostics:
                from sdn3d.editing.appearance import render_maps

                out["reconstruction"] = render_maps(out["source_maps"], self.models.textural)
        record = self._photo_record(drawn, ops) if drawn.photo is not None else self._compose_record(drawn)
        return out | record

    def _compose_record(self, drawn: Drawn) -> dict[str, Any]:
        """appearance=generator: the picture as uint8 and edit.json's ``compose`` record."""
        settings, region = self.settings.compose, drawn.region
        edited = to_uint8(drawn.image) if region is None else drawn.image.permute(1, 2, 0).numpy()
        info = {**settings.to_dict(), "output_size": [edited.shape[1], edited.shape[0]],
                "edited_objects": drawn.edited_ids.tolist()}
        if region is not None:
            info |= {"region_pixels": int(region.sum()), "region_fraction": float(region.float().mean())}
        return {"edited": edited, "region": region, "source_map": None, "compose": info, "photo": None,
                "warnings": []}

    def _photo_record(self, drawn: Drawn, ops: list[EditOp]) -> dict[str, Any]:
        """appearance=photo: the picture, where each pixel came from and edit.json's ``photo`` record."""
        result = drawn.photo
        coded = [op for op in ops if isinstance(op, SetBackgroundCode) or (isinstance(op, SetCode)
                                                                          and op.color is None)]
        if coded:
            result.warnings.append(f"{len(coded)} recolor op(s) by code or sample change what the generator draws; "
                                   "appearance=photo draws the photo's pixels and repaints a car only for "
                                   "`color: <name>` (or use appearance=generator)")
        edited = result.image.permute(1, 2, 0).numpy()
        info = {"mode": "photo", "output_size": [edited.shape[1], edited.shape[0]]}
        return {"edited": edited, "region": None, "source_map": result.source, "compose": info,
                "photo": {"settings": self.settings.photo.to_dict(), **result.summary()},
                "warnings": list(result.warnings)}


# -- records (edit.json, the listing) ---------------------------------------------------------------


def proposals_record(scene: SceneCode) -> dict:
    """Where the scene's objects and semantics came from, with the oracle labelled (edit.json ``proposals``)."""
    source, semantic = scene.meta.get("proposals"), scene.meta.get("semantic")
    oracle = source == "gt" or semantic == "gt"
    label = (PROPOSAL_LABELS["gt"] if source == "gt" and semantic == "gt" else
             "oracle: ground-truth masks, the semantic branch's semantics" if source == "gt" else
             PROPOSAL_LABELS["boxes"] + {"branch": "; semantics from the semantic branch",
                                         "gt": "; ground-truth semantics (oracle)",
                                         "none": "; no semantics"}.get(semantic, "") if source == "boxes" else
             PROPOSAL_LABELS["semantic"])
    boxes = len(scene.meta.get("boxes", []))
    if boxes and source != "boxes":
        label += f"; and {boxes} object(s) named by a box (GrabCut masks, 3D fitted)"
    record = {"masks": source, "semantics": semantic, "oracle": oracle, "label": label}
    return record | {"box_objects": boxes} if boxes else record


def boxes_record(scene: SceneCode, frame: PixelFrame | None) -> list[dict]:
    """``scene.meta['boxes']`` (:class:`~sdn3d.box_objects.BoxFit`) as edit.json and the listing show them, each box
    also in the input image's pixels (``input_box``)."""
    from sdn3d.box_objects import box_fits

    out = []
    for record in (fit.to_json() for fit in box_fits(scene.meta)):
        x0, y0, x1, y1 = record["box"]
        if frame is not None:
            (x0, y0), (x1, y1) = (frame.to_input((u - 0.5, v - 0.5)) for u, v in ((x0, y0), (x1, y1)))
            x0, y0, x1, y1 = x0 + 0.5, y0 + 0.5, x1 + 0.5, y1 + 0.5
        out.append({**record, "input_box": [round(v, 1) for v in (x0, y0, x1, y1)]})
    return out


class BoxRefusedError(EditSpecError):
    """Boxes of an edit spec's ``objects`` where no vehicle is (:func:`refuse_boxes`); ``objects``: their indices,
    ``reasons``: why, per index."""

    def __init__(self, message: str, objects: list[int], reasons: dict[int, str]) -> None:
        super().__init__(message)
        self.objects, self.reasons = objects, reasons


def refuse_boxes(spec: EditSpec | None, derendered: Derendered, fit: Any = None) -> None:
    """Raise :class:`BoxRefusedError` naming each of ``spec``'s ``objects`` (without ``force: true``) where GrabCut,
    the road plane or the 3D fit says no vehicle is (:func:`sdn3d.box_masks.no_vehicle`; ``fit``: the box fit's
    settings, for the camera's height over the road). Nothing is added then: the edit is refused as a whole."""
    from sdn3d.box_masks import no_vehicle
    from sdn3d.geometric.fit import FitSettings

    if spec is None or not spec.objects:
        return
    from sdn3d.editing.frame import input_intrinsics

    inp = derendered.input
    intr = input_intrinsics(inp.intrinsics, inp.frame)  # the input's own pixels, as the spec's boxes are given
    height = (fit or FitSettings()).camera_height
    reasons = {}
    for obj, record in zip(spec.objects, derendered.boxes, strict=False):
        if obj.force:
            continue
        missing = record.get("why") if record["fit_iou"] is None else None
        why = no_vehicle(record["input_box"], intr.fx, intr.fy, intr.cy, tuple(inp.input_size), camera_height=height,
                         fit_iou=record["fit_iou"], fit_missing=missing)
        if why:
            reasons[obj.index] = why
    if reasons:
        lines = [f"objects[{i}] (box {[round(v, 1) for v in spec.objects[i].box]}, {spec.objects[i].class_}): no "
                 f"vehicle there: {why}" for i, why in reasons.items()]
        raise BoxRefusedError("\n".join(lines) + "\nNothing was added. To add "
                              + ("it" if len(reasons) == 1 else "them") + " anyway, give "
                              + ("it" if len(reasons) == 1 else "each") + " force: true", sorted(reasons), reasons)


def fit_warnings(box_records: list[dict], poor_iou: float | None) -> list[str]:
    """One warning per object named by a box (:func:`boxes_record`) whose 3D fit is poor (under ``poor_iou``) or
    missing (before any edit)."""
    out = []
    for record in box_records:
        if record["fit_iou"] is None:
            out.append(f"box object {record['id']} (box {record['input_box']}): {record['why']}; it can be deleted "
                       "or recoloured but not moved, turned or zoomed")
        elif record.get("fit_note"):  # the mask was too small or thin to fit: the branch's prediction was kept
            out.append(f"box object {record['id']} (box {record['input_box']}): {record['fit_note']}")
        elif record["poor_fit"]:
            out.append(f"box object {record['id']} (box {record['input_box']}): its fitted 3D shape matches its mask "
                       f"poorly (silhouette IoU {record['fit_iou']:.2f} < {poor_iou}); a moved "
                       "or turned copy may look wrong. A tighter box around the whole car may help")
    return out


def object_origins(scene: SceneCode, ids: Any, box_records: list[dict]) -> list[dict]:
    """Per object of ``ids``: where its mask and its 3D pose came from and, for an object named by a box
    (:func:`boxes_record`), how well its fit matched (edit.json ``edited_objects``)."""
    boxes = {r["id"]: r for r in box_records}
    source, refined = scene.meta.get("proposals"), bool(scene.meta.get("refined", False))
    table = scene.objects
    out = []
    for iid in [int(i) for i in ids]:
        if iid in boxes:
            r = boxes[iid]
            out.append({"id": iid, "mask": f"in the box {r['input_box']} (input pixels): {r['mask']}",
                        "pose": r["pose"], "fit_iou": r["fit_iou"], "poor_fit": r["poor_fit"]})
            continue
        rows = (table.instance_id == iid).nonzero().flatten()
        geometry = bool(rows.numel()) and bool(table.template_id[rows[0]] >= 0)
        out.append({"id": iid, "mask": "ground truth (oracle)" if source == "gt" else "the semantic branch",
                    "pose": None if not geometry else "the geometric branch" + (", refined by L_reproj" if refined
                                                                                 else ""),
                    "fit_iou": None, "poor_fit": None})
    return out
