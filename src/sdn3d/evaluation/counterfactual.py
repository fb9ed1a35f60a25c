"""The counterfactual benchmark (issue 41 item 4): turns and deletes scored on exact pairs.

``sdn3d-synth counterfactual_cars=N`` writes, per target car of a test frame, the frame re-rendered with only that
car turned in place by each angle, and without it (:mod:`sdn3d.data.counterfactual`, docs/DATA.md). Here each
pair's edit (``Rotate(car, radians(angle))`` or ``Delete(car)``) is applied to the source frame's scene and drawn by
every method through :func:`~sdn3d.editing.appearance.appearance_renderer`, then scored against the exact render:

- **source scenes** (:data:`SOURCE_LABELS`, every report names them): ``oracle`` = the frame's ground-truth
  geometry (:func:`~sdn3d.data.scene_gt.scene_from_frame`), so the drawing alone is measured; ``gt`` = the
  geometric branch on the ground-truth masks; ``semantic`` = the branches on their own masks (what a user gets).
  A predicted scene's target car is the object whose mask overlaps the pair's source mask best (IoU at least
  :attr:`CounterfactualSettings.match_iou`, else the pair is *missed* for that scene, counted apart);
- **methods** (:func:`methods`): ``photo:<fill>`` = the photo appearance with each fill of
  :attr:`CounterfactualSettings.fills` (``photo:auto``, the default before ``rays``, is the reference of every paired
  comparison, :data:`REFERENCE`; ``photo:generator`` needs the generator), ``generator`` = the generator appearance
  composed into the frame (``compose='edited'``; with a generator only), ``2d`` / ``2d+`` = the 2D baselines of the
  photo appearance (:func:`~sdn3d.evaluation.baselines.baseline_photo`: the car's own pixels pasted in place, for
  ``2d+`` squeezed by ``|cos angle|``, over the default fill);
- **regions and metrics** (masks at the pairs' size, which is the frames' stored size: everything is drawn there):
  a turn on the car's pixels in the target render (``car``: ``psnr``, ``l1``, and ``flat``, the share of those
  pixels the photo appearance drew as flat colour, :data:`FLAT_SOURCES` of its per-pixel source map), and on
  ``changed`` = car ∪ vacated ∪ shadow band; a delete on ``hole`` = vacated ∪ shadow band (``psnr``, ``l1``) and
  the **residual darkening** of the shadow band: ``darkening(x) = 1 - mean Y(x) over the band's road pixels /
  mean Y(x) over the surrounding road ring`` (``Y = 0.2126 R + 0.7152 G + 0.0722 B`` of the sRGB values in
  [0, 1]; road = the source frame's ground-truth Road class; the ring = road pixels within
  :attr:`CounterfactualSettings.ring_px` of the band or the vacated region, outside both and outside every
  car of the source frame). ``darkening`` is the method's, ``darkening_error = |darkening(method) -
  darkening(target)|`` (the target render has no shadow there, so its value is the road's own shading: ~0).
  PSNR is ``10 log10(1 / max(MSE, 1e-6))`` (at most 60 dB: an exact match does not make a mean infinite);
- **summaries** per source scene, bin (``turn 15``, ``turn 45``, ``turn 90``, ``turn 180``, ``delete``; a 0-degree
  turn has its own bin), method and metric: the mean with a 95 % bootstrap interval; **paired comparisons** of each
  method against :data:`REFERENCE` over the same pairs (:func:`~sdn3d.evaluation.paired.paired_difference`). Every
  interval resamples whole **cars** (:attr:`~sdn3d.data.counterfactual.CounterfactualPair.car`): one parked car
  appears in many frames, both variations and every angle, and its pairs are one piece of evidence, not many.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.data.counterfactual import CounterfactualIndex, CounterfactualPair, load_pair_mask, load_pair_rgb
from sdn3d.data.edit_benchmark import BenchmarkOperation
from sdn3d.data.frames import load_frame
from sdn3d.data.records import FrameRecord, load_instances, load_semantic
from sdn3d.data.scene_gt import frame_photo, ground_truth, scene_from_frame
from sdn3d.derender import PROPOSAL_LABELS, Models, derender, encode_scene
from sdn3d.editing.appearance import Appearance, appearance_renderer
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.compose import ComposeSettings
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Delete, Rotate
from sdn3d.editing.photo.settings import FILL_METHODS, FLAT_CODES, SOURCE_NAMES, PhotoSettings
from sdn3d.editing.pick import projected_centers
from sdn3d.errors import UserInputError
from sdn3d.evaluation.baselines import BASELINE_MODES, baseline_photo
from sdn3d.evaluation.paired import paired_difference
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.scene.code import DEFAULT_CODE_DIM, SceneCode

if TYPE_CHECKING:
    from sdn3d.geometric.fit import FitSettings

__all__ = ["SOURCES", "SOURCE_LABELS", "REFERENCE", "FLAT_SOURCES", "PSNR_MSE_FLOOR", "LUMA",
           "CounterfactualSettings", "PairResult", "method_names", "methods", "pair_bin", "luminance", "darkening",
           "road_ring",
           "evaluate_target", "run_counterfactual", "summarize", "comparisons", "counterfactual_markdown",
           "HIGHER_IS_BETTER"]

#: The source scenes (module doc), in report order.
SOURCES = ("oracle", "gt", "semantic")
SOURCE_LABELS = {"oracle": "oracle: ground-truth geometry", "gt": "oracle: ground-truth masks",
                 "semantic": PROPOSAL_LABELS["semantic"]}
#: The photo default before ``fill='rays'`` (the fill every earlier record compared against): the reference of every
#: paired comparison.
REFERENCE = "photo:auto"
#: Names of the photo appearance's source codes that are flat colour, no pixel of the input behind them
#: (:data:`~sdn3d.editing.photo.settings.FLAT_CODES`: the body-colour fallback and a never-seen part's default).
FLAT_SOURCES = tuple(SOURCE_NAMES[c] for c in FLAT_CODES)
#: Masked MSE floor of PSNR (60 dB at most).
PSNR_MSE_FLOOR = 1e-6
#: Rec. 709 luma weights of the darkening measure.
LUMA = (0.2126, 0.7152, 0.0722)
#: Metrics where a larger value is better (the rest: smaller).
HIGHER_IS_BETTER = frozenset({"psnr"})
#: What each kind of pair is scored on: ``{kind: {region: metrics}}``.
SCORES = {"turn": {"car": ("psnr", "l1", "flat"), "changed": ("psnr", "l1")},
          "delete": {"hole": ("psnr", "l1", "darkening", "darkening_error")}}


@dataclass(frozen=True)
class CounterfactualSettings:
    """How the counterfactual benchmark runs.

    Attributes:
        sources: the source scenes (:data:`SOURCES`).
        fills: the photo appearance's fills, one method each (``photo:<fill>``; ``generator`` needs the generator).
        generator: also the generator appearance (``compose='edited'``) when a generator is given.
        baselines: the 2D baselines of the photo appearance (``2d``, ``2d+``).
        photo: the photo appearance's other settings (each method sets its own ``fill``).
        compose: the generator appearance's compose settings.
        min_pixels: visible pixels an object needs for 3D geometry in :func:`~sdn3d.derender.derender`.
        fit: the test-time fit of the de-rendered sources' vehicles (:mod:`sdn3d.proposal_fit`), or None.
        match_iou: a predicted object is the target car when its mask's IoU with the source mask is at least this.
        ring_px: width of the road ring around a delete's shadow band (None: ``max(3, round(W / 50))``).
        limit: at most this many target cars (each with all its pairs; None: all).
        kinds: the kinds of pairs evaluated.
    """

    sources: tuple[str, ...] = ("oracle",)
    fills: tuple[str, ...] = ("auto", "telea", "patchmatch", "rays")
    generator: bool = True
    baselines: tuple[str, ...] = BASELINE_MODES
    photo: PhotoSettings = field(default_factory=PhotoSettings)
    compose: ComposeSettings = field(default_factory=ComposeSettings)
    min_pixels: int = 64
    fit: FitSettings | None = None
    match_iou: float = 0.5
    ring_px: int | None = None
    limit: int | None = None
    kinds: tuple[str, ...] = ("turn", "delete")

    def __post_init__(self) -> None:
        for name, values, allowed in (("sources", self.sources, SOURCES), ("fills", self.fills, FILL_METHODS),
                                      ("baselines", self.baselines, BASELINE_MODES),
                                      ("kinds", self.kinds, ("turn", "delete"))):
            values = tuple(str(v) for v in values)
            if len(set(values)) != len(values) or not set(values) <= set(allowed):
                raise UserInputError(f"counterfactual {name} must list distinct values of {list(allowed)}, "
                                     f"got {list(values)}")
            object.__setattr__(self, name, values)
        if not self.sources:
            raise UserInputError("counterfactual sources must name at least one source scene")
        if self.limit is not None and self.limit < 0:
            raise UserInputError(f"counterfactual limit must be >= 0, got {self.limit}")


def method_names() -> tuple[str, ...]:
    """Every method a run may evaluate (:func:`methods`): a reference (``counterfactual_reference``) must be one."""
    return (*(f"photo:{f}" for f in FILL_METHODS), "generator", *BASELINE_MODES)


def methods(settings: CounterfactualSettings, has_generator: bool) -> tuple[str, ...]:
    """The methods evaluated (module doc), :data:`REFERENCE` first when present."""
    fills = [f for f in settings.fills if f != "generator" or has_generator]
    out = [f"photo:{f}" for f in sorted(fills, key=lambda f: f != "auto")]
    if settings.generator and has_generator:
        out.append("generator")
    return (*out, *settings.baselines)


def pair_bin(pair: CounterfactualPair) -> str:
    """``'turn <angle>'`` or ``'delete'``."""
    return "delete" if pair.kind == "delete" else f"turn {pair.angle_deg:g}"


def luminance(image: Tensor) -> Tensor:
    """``(H, W)`` luma of ``image (3, H, W)`` in [0, 1] (:data:`LUMA`)."""
    w = torch.tensor(LUMA, dtype=image.dtype, device=image.device)
    return (image * w[:, None, None]).sum(0)


def road_ring(band: Tensor, vacated: Tensor, road: Tensor, cars: Tensor, ring_px: int) -> Tensor:
    """``(H, W)`` bool road pixels within ``ring_px`` (square window) of ``band | vacated``, outside both and outside
    ``cars``."""
    hole = (band | vacated).float()[None, None]
    near = F.max_pool2d(hole, 2 * ring_px + 1, stride=1, padding=ring_px)[0, 0] > 0
    return near & road & ~band & ~vacated & ~cars


def darkening(image: Tensor, band: Tensor, ring: Tensor) -> float:
    """``1 - mean Y(image) over band / mean Y(image) over ring`` (module doc); NaN when either is empty."""
    if not bool(band.any()) or not bool(ring.any()):
        return float("nan")
    y = luminance(image.float())
    around = float(y[ring].mean())
    return float("nan") if around <= 0 else 1.0 - float(y[band].mean()) / around


def _psnr_l1(pred: Tensor, target: Tensor, mask: Tensor) -> dict[str, float]:
    if not bool(mask.any()):
        return {"psnr": float("nan"), "l1": float("nan")}
    diff = (pred.float() - target.float())[:, mask]
    mse = float((diff**2).mean())
    return {"psnr": 10 * math.log10(1.0 / max(mse, PSNR_MSE_FLOOR)), "l1": float(diff.abs().mean())}


def _shares(source: Tensor, mask: Tensor) -> dict[str, float]:
    if not bool(mask.any()):
        return {}
    counts = torch.bincount(source[mask].long().flatten(), minlength=len(SOURCE_NAMES)).float()
    shares = (counts / counts.sum()).tolist()
    return {name: float(s) for name, s in zip(SOURCE_NAMES, shares, strict=False)}


@dataclass
class PairResult:
    """One pair scored in one source scene (``car``: the pair's physical car, the intervals' resampling unit):
    ``metrics[method][region][metric]``; ``sources[method]``: the photo
    appearance's source-map shares on the scored region (``car`` / ``hole``); ``reference``: the target's and the
    source frame's own darkening (deletes); ``errors``: ``{method or 'pair': message}``; ``iou``: the target car's
    match in the scene (1 for the oracle)."""

    key: str
    source: str
    bin: str
    kind: str
    pixels: dict[str, int]
    car: str
    metrics: dict[str, dict[str, dict[str, float]]] = field(default_factory=dict)
    sources: dict[str, dict[str, float]] = field(default_factory=dict)
    reference: dict[str, float] = field(default_factory=dict)
    errors: dict[str, str] = field(default_factory=dict)
    iou: float = float("nan")
    draw_ms: dict[str, float] = field(default_factory=dict)

    def to_json(self) -> dict:
        return {"key": self.key, "source": self.source, "bin": self.bin, "kind": self.kind, "pixels": self.pixels,
                "car": self.car, "iou": self.iou, "metrics": self.metrics, "sources": self.sources,
                "reference": self.reference, "errors": self.errors, "draw_ms": self.draw_ms}


def _source_scene(source: str, record: FrameRecord, image: Tensor, intrinsics, models: Models | None,
                  settings: CounterfactualSettings, size: tuple[int, int]) -> SceneCode:
    textural = models.textural if models is not None else None
    if source == "oracle":
        scene = scene_from_frame(record, size, textural.spec.code_dim if textural is not None else DEFAULT_CODE_DIM)
        return encode_scene(scene, image, textural) if textural is not None else scene
    proposals = "semantic" if source == "semantic" else "gt"
    return derender(image, intrinsics, models, proposals, ground_truth(record, size), min_pixels=settings.min_pixels,
                    fit=settings.fit, photo=frame_photo(record, size))


def _match(scene: SceneCode, instance_id: int, source_mask: Tensor) -> tuple[int | None, float]:
    """``(the scene's id of the target car, its mask IoU)``: the object with geometry overlapping the source mask
    best (None when none has geometry)."""
    objects = scene.objects
    best, best_iou = None, 0.0
    for row in range(len(objects)):
        if not bool(objects.has_geometry[row]):
            continue
        mask = objects.mask[row].bool()
        union = int((mask | source_mask).sum())
        iou = int((mask & source_mask).sum()) / union if union else 0.0
        if iou > best_iou or (iou == best_iou and int(objects.instance_id[row]) == instance_id):
            best, best_iou = int(objects.instance_id[row]), iou
    return best, best_iou


def _renderers(names: Sequence[str], settings: CounterfactualSettings, models: Models | None) -> dict:
    textural = models.textural if models is not None else None
    out = {}
    for name in names:
        if name.startswith("photo:"):
            photo = PhotoSettings(**{**settings.photo.to_dict(), "fill": name.split(":", 1)[1]})
            out[name] = appearance_renderer(Appearance.PHOTO, photo=photo, textural=textural)
        elif name == "generator":
            out[name] = appearance_renderer(Appearance.GENERATOR, compose=settings.compose, textural=textural)
    return out


def evaluate_target(pairs: Sequence[CounterfactualPair], record: FrameRecord, index: CounterfactualIndex,
                    models: Models | None, settings: CounterfactualSettings) -> list[PairResult]:
    """Every pair of one target car (same frame and car), in every source scene, by every method."""
    size = index.image_size
    root = index.root
    frame = load_frame(record, size, semantic=False, instances=False)
    image = frame.image
    first = pairs[0]
    source_mask = torch.from_numpy(load_pair_mask(root, first, "source_mask"))
    road = torch.from_numpy(load_semantic(record)).long() == VKITTI_CLASS_INDEX["Road"]
    cars = torch.from_numpy(load_instances(record)).long() != 0
    if tuple(road.shape) != (size[1], size[0]):
        raise UserInputError(f"{record.key}: frames stored at {tuple(road.shape[::-1])}, the counterfactual pairs at "
                             f"{size}: the benchmark needs the tree sdn3d-synth wrote")
    ring_px = settings.ring_px or max(3, round(size[0] / 50))
    names = methods(settings, models is not None and models.textural is not None)
    identity = PixelFrame(size, size)
    loaded = []
    for pair in pairs:
        target = torch.from_numpy(load_pair_rgb(root, pair)).permute(2, 0, 1).float() / 255
        masks = {k: torch.from_numpy(load_pair_mask(root, pair, k)) for k in ("target_mask", "vacated", "shadow")}
        loaded.append((pair, target, masks))
    results: list[PairResult] = []
    for source in settings.sources:
        base = [PairResult(p.key, source, pair_bin(p), p.kind, dict(p.pixels), p.car) for p in pairs]
        try:
            scene = _source_scene(source, record, image, frame.intrinsics, models, settings, size)
            iid, iou = _match(scene, first.instance_id, source_mask)
            if iid is None or iou < settings.match_iou:
                raise ValueError(f"missed: no object of the scene matches the target car (best IoU {iou:.2f} < "
                                 f"{settings.match_iou})")
        except ValueError as exc:
            for r in base:
                r.errors["pair"] = str(exc)
            results.extend(base)
            continue
        renderers = _renderers(names, settings, models)
        states = {n: r.prepare(image, identity, scene) for n, r in renderers.items()}
        centre = _centre(scene, iid)
        for result, (pair, target, masks) in zip(base, loaded, strict=True):
            result.iou = iou
            _score_pair(result, pair, scene, iid, centre, image, target, masks, renderers, states, names, settings,
                        road, cars, ring_px, models)
        results.extend(base)
    return results


def _centre(scene: SceneCode, iid: int) -> list[float]:
    uv, _ = projected_centers(scene)
    row = int((scene.objects.instance_id == iid).nonzero()[0, 0])
    return [float(v) for v in uv[row].tolist()]


def _score_pair(result: PairResult, pair: CounterfactualPair, scene: SceneCode, iid: int, centre: list[float],
                image: Tensor, target: Tensor, masks: dict[str, Tensor], renderers: dict, states: dict,
                names: Sequence[str], settings: CounterfactualSettings, road: Tensor, cars: Tensor, ring_px: int,
                models: Models | None) -> None:
    delete = pair.kind == "delete"
    angle = 0.0 if delete else math.radians(float(pair.angle_deg))
    ops = [Delete(iid)] if delete else [Rotate(iid, angle)]
    bench_op = (BenchmarkOperation.delete(tuple(centre)) if delete else
                BenchmarkOperation.modify(tuple(centre), tuple(centre), 1.0, angle))
    car = masks["target_mask"]
    regions = ({"hole": masks["vacated"] | masks["shadow"]} if delete else
               {"car": car, "changed": car | masks["vacated"] | masks["shadow"]})
    band = masks["shadow"] & road
    ring = road_ring(masks["shadow"], masks["vacated"], road, cars, ring_px) if delete else None
    if delete:
        result.reference = {"target": darkening(target, band, ring), "source": darkening(image, band, ring),
                            "band_road_pixels": int(band.sum()), "ring_pixels": int(ring.sum())}
    try:
        edited = apply_edits(scene, ops)
    except ValueError as exc:
        result.errors["pair"] = str(exc)
        return
    for name in names:
        t0 = time.perf_counter()
        try:
            flat_source = None
            if name in renderers:
                drawn = renderers[name].draw(states[name], edited, ops)
                picture = drawn.image.float()
                if drawn.photo is not None:
                    flat_source = drawn.photo.source
            else:
                picture = baseline_photo(image, scene, [bench_op], name, None, settings.photo)
        except ValueError as exc:
            result.errors[name] = str(exc)
            continue
        result.draw_ms[name] = 1000 * (time.perf_counter() - t0)
        picture = picture.clamp(0, 1)
        scores = {region: _psnr_l1(picture, target, mask) for region, mask in regions.items()}
        if delete:
            dark = darkening(picture, band, ring)
            scores["hole"] |= {"darkening": dark, "darkening_error": abs(dark - result.reference["target"])}
        else:
            shares = _shares(flat_source, car) if flat_source is not None else {}
            scores["car"]["flat"] = (sum(shares.get(s, 0.0) for s in FLAT_SOURCES) if shares else float("nan"))
            if shares:
                result.sources[name] = shares
        result.metrics[name] = scores


def run_counterfactual(index: CounterfactualIndex, records: dict[tuple[str, str, int], FrameRecord],
                       models: Models | None, settings: CounterfactualSettings,
                       progress: Callable[[int, int, list[PairResult]], None] | None = None) -> list[PairResult]:
    """Evaluate every pair of ``index`` (``settings.limit`` target cars at most); frames from ``records``
    (``{(world, variation, frame): record}``). A target whose frame is missing is reported, not raised.

    Raises:
        UserInputError: a source scene needs a branch ``models`` lacks (``gt``: the geometric branch; ``semantic``:
            the semantic one too), or the frames are not stored at the pairs' size.
    """
    for source in settings.sources:
        if source != "oracle" and (models is None or models.geometric is None
                                   or (source == "semantic" and models.semantic is None)):
            need = "checkpoints.geometric" + (" and checkpoints.semantic" if source == "semantic" else "")
            raise UserInputError(f"source scene {source!r} ({SOURCE_LABELS[source]}) needs {need}")
    groups: dict[tuple, list[CounterfactualPair]] = {}
    for p in index.pairs:
        if p.kind in settings.kinds:
            groups.setdefault(p.target_key, []).append(p)
    chosen = list(groups.items())[: settings.limit] if settings.limit is not None else list(groups.items())
    out: list[PairResult] = []
    for n, ((world, variation, frame, _), pairs) in enumerate(chosen):
        record = records.get((world, variation, frame))
        if record is None:
            rows = [PairResult(p.key, s, pair_bin(p), p.kind, dict(p.pixels), p.car,
                               errors={"pair": f"frame {world}/{variation}/{frame:05d} not in the dataset"})
                    for s in settings.sources for p in pairs]
        else:
            rows = evaluate_target(pairs, record, index, models, settings)
        out.extend(rows)
        if progress is not None:
            progress(n + 1, len(chosen), rows)
    return out


def _mean_interval(values: list[float], cars: list[str]) -> dict:
    """The mean of ``values`` with its bootstrap interval, resampling whole ``cars`` (one label per value)."""
    if not values:
        return {"mean": float("nan"), "low": float("nan"), "high": float("nan"), "n": 0, "cars": 0}
    d = paired_difference(values, [0.0] * len(values), higher_is_better=True, groups=cars)
    return {"mean": d.mean, "low": d.low, "high": d.high, "median": float(np.median(values)), "n": d.n,
            "cars": d.groups}


def _bins(results: Sequence[PairResult]) -> list[str]:
    def order(b: str) -> tuple:
        return (1, 0.0) if b == "delete" else (0, abs(float(b.split()[1])))

    return sorted({r.bin for r in results}, key=order)


def _values(rows: Sequence[PairResult], method: str, region: str, metric: str) -> list[float | None]:
    out = []
    for r in rows:
        v = r.metrics.get(method, {}).get(region, {}).get(metric)
        out.append(float(v) if isinstance(v, (int, float)) and math.isfinite(v) else None)
    return out


def _scored(rows: Sequence[PairResult], method: str, region: str, metric: str) -> tuple[list[float], list[str]]:
    """The finite values of ``method``'s ``region.metric`` over ``rows`` and each one's car."""
    pairs = [(v, r.car) for v, r in zip(_values(rows, method, region, metric), rows, strict=True) if v is not None]
    return [v for v, _ in pairs], [c for _, c in pairs]


def summarize(results: Sequence[PairResult], method_names: Sequence[str]) -> dict:
    """``{source: {bin: {'pairs', 'scored', 'missed', 'methods': {method: {region: {metric: {mean, low, high, median,
    n, cars}}}}, 'reference': {...}}}}`` (deletes' ``reference``: the target's and the source frame's own darkening);
    intervals resample whole cars (module doc)."""
    out: dict = {}
    for source in dict.fromkeys(r.source for r in results):
        out[source] = {}
        mine = [r for r in results if r.source == source]
        for b in _bins(mine):
            rows = [r for r in mine if r.bin == b]
            kind = rows[0].kind
            entry = {"pairs": len(rows), "scored": sum(1 for r in rows if r.metrics),
                     "missed": sum(1 for r in rows if "pair" in r.errors), "methods": {}}
            for m in method_names:
                entry["methods"][m] = {region: {metric: _mean_interval(*_scored(rows, m, region, metric))
                                                for metric in metrics}
                                       for region, metrics in SCORES[kind].items()}
            if kind == "delete":
                kept = {k: [r for r in rows if k in r.reference and math.isfinite(r.reference[k])]
                        for k in ("target", "source")}
                entry["reference"] = {k: _mean_interval([r.reference[k] for r in kept[k]], [r.car for r in kept[k]])
                                      for k in kept}
            out[source][b] = entry
    return out


def comparisons(results: Sequence[PairResult], method_names: Sequence[str], reference: str = REFERENCE) -> dict:
    """``{source: {bin: {method: {'<region>.<metric>': PairedDifference dict}}}}``: each method minus ``reference``
    over the pairs where both have a finite value, resampling whole cars (``groups``: how many)."""
    out: dict = {}
    for source in dict.fromkeys(r.source for r in results):
        out[source] = {}
        mine = [r for r in results if r.source == source]
        for b in _bins(mine):
            rows = [r for r in mine if r.bin == b]
            out[source][b] = {}
            for m in method_names:
                if m == reference:
                    continue
                out[source][b][m] = {}
                for region, metrics in SCORES[rows[0].kind].items():
                    for metric in metrics:
                        if metric == "darkening":
                            continue  # signed: compared through darkening_error
                        a, c = _values(rows, m, region, metric), _values(rows, reference, region, metric)
                        pairs = [(x, y, r.car) for x, y, r in zip(a, c, rows, strict=True)
                                 if x is not None and y is not None]
                        d = paired_difference([x for x, _, _ in pairs], [y for _, y, _ in pairs],
                                              higher_is_better=metric in HIGHER_IS_BETTER,
                                              groups=[g for _, _, g in pairs])
                        out[source][b][m][f"{region}.{metric}"] = d.to_dict()
    return out


def _ci(stat: dict, digits: int = 2, scale: float = 1.0) -> str:
    if not stat or not stat.get("n"):
        return "–"
    return (f"{stat['mean'] * scale:.{digits}f} [{stat['low'] * scale:.{digits}f}, "
            f"{stat['high'] * scale:.{digits}f}]")


def _count(stat: dict) -> str:
    return f"{stat['n']} ({stat['cars']})" if stat.get("n") else "0"


def _delta(d: dict | None, digits: int = 2, scale: float = 1.0) -> str:
    if not d or not d.get("n"):
        return "–"
    return (f"{d['mean'] * scale:+.{digits}f} [{d['low'] * scale:+.{digits}f}, {d['high'] * scale:+.{digits}f}] "
            f"{d['wins']}/{d['losses']}/{d['ties']}")


def counterfactual_markdown(summary: dict, comps: dict, info: dict) -> str:
    """``counterfactual.md``: per source scene a turns table (per angle bin and method) and a deletes table."""
    reference = info.get("reference", REFERENCE)
    what = " (the photo default before `rays`)" if reference == REFERENCE else ""
    lines = ["# Counterfactual benchmark: turns and deletes on exact pairs", "",
             f"Data: {info.get('data')}, pairs drawn at {info.get('image_size')} (the frames' stored size). "
             f"Reference of every paired difference: `{reference}`{what}. Means with 95 % "
             "bootstrap intervals that resample whole cars (a parked car's pairs in every frame, variation and angle "
             "are drawn together); n = pairs (cars); a paired difference is `method - reference` [95 % interval] "
             "wins/losses/ties (by the metric's direction). PSNR in dB (at most 60), L1 on [0, 1], flat = share of "
             "the car's target pixels the photo appearance drew as flat colour (source map `fallback` or "
             "`default`), in %.", ""]
    if "methods" in info and reference not in info["methods"]:  # e.g. counterfactual_fills=[rays]: nothing to pair
        lines += [f"`{reference}` was not scored here (`counterfactual_fills` without `auto`, or another "
                  "`counterfactual_reference` than the methods run), so the columns of differences against it are "
                  "empty; `counterfactual.json` holds every pair's scores to pair any two methods.", ""]
    if info.get("generator_note"):
        lines += [info["generator_note"], ""]
    for source, bins in summary.items():
        lines += [f"## Source scene: {SOURCE_LABELS[source]}", ""]
        turns = [b for b in bins if b != "delete"]
        if turns:
            lines += ["### Turns (on the car's target pixels)", "",
                      "| bin | method | n | PSNR car | L1 car | flat % | PSNR car+vacated+shadow | ΔPSNR car vs ref "
                      "| ΔL1 car vs ref | Δflat % vs ref |", "|---|---|---|---|---|---|---|---|---|---|"]
            for b in turns:
                entry = bins[b]
                for m, regions in entry["methods"].items():
                    car, changed = regions["car"], regions["changed"]
                    d = comps.get(source, {}).get(b, {}).get(m, {})
                    lines.append(f"| {b} | {m} | {_count(car['psnr'])} | {_ci(car['psnr'])} | {_ci(car['l1'], 4)} | "
                                 f"{_ci(car['flat'], 1, 100)} | {_ci(changed['psnr'])} | "
                                 f"{_delta(d.get('car.psnr'))} | {_delta(d.get('car.l1'), 4)} | "
                                 f"{_delta(d.get('car.flat'), 1, 100)} |")
                if entry["missed"]:
                    lines.append(f"| {b} | (missed: {entry['missed']} of {entry['pairs']} pairs) | | | | | | | | |")
            lines.append("")
        if "delete" in bins:
            entry = bins["delete"]
            ref = entry.get("reference", {})
            lines += ["### Deletes (on the vacated region plus the shadow band)", "",
                      f"Darkening of the shadow band against the surrounding road ring (1 - mean luma in band / "
                      f"mean luma in ring): the target render {_ci(ref.get('target', {}), 3)}, the input "
                      f"(shadow still there) {_ci(ref.get('source', {}), 3)}.", "",
                      "| method | n | PSNR | L1 | darkening | darkening error | ΔPSNR vs ref "
                      "| Δdarkening error vs ref |",
                      "|---|---|---|---|---|---|---|---|"]
            for m, regions in entry["methods"].items():
                h = regions["hole"]
                d = comps.get(source, {}).get("delete", {}).get(m, {})
                lines.append(f"| {m} | {_count(h['psnr'])} | {_ci(h['psnr'])} | {_ci(h['l1'], 4)} | "
                             f"{_ci(h['darkening'], 3)} | {_ci(h['darkening_error'], 3)} | "
                             f"{_delta(d.get('hole.psnr'))} | {_delta(d.get('hole.darkening_error'), 3)} |")
            if entry["missed"]:
                lines.append(f"| (missed: {entry['missed']} of {entry['pairs']} pairs) | | | | | | | |")
            lines.append("")
    return "\n".join(lines)
