"""Per-edit latency of 3D-SDN (de-render + edit + render, + compose) at 624x192 on the CPU; prints JSON.

    python benchmarks/edit_latency.py [--threads 1 [2 ...]] [--repeats 3] [--entries 3] [--cars 11]
                                      [--presets demo paper] [--geometric CKPT] [--textural CKPT]
                                      [--data DIR] [--out FILE] [--no-reference] [--semantic]
                                      [--device cpu|cuda] [--input-size 1242 375]

What one edit is (the path of :func:`sdn3d.evaluation.edit_benchmark.evaluate_entry`, ``proposals='gt'``):
a source frame of a synthetic Virtual KITTI dataset written at ``--size`` (``sdn3d-synth`` recipe, ``--cars`` cars per
frame, into a temporary folder unless ``--data`` names an existing one) and one entry of its editing
benchmark file (``vkitti_edit_benchmark.json``: deletes and modifies of several cars), split into

- ``derender``: :func:`sdn3d.derender.derender` (ground-truth masks and semantics read from disk, the
  geometric branch on every object's crop, the texture encoder); its ``geometric`` and ``encoder``
  parts are timed inside it too;
- ``edit_ops``: :func:`sdn3d.editing.apply.ops_from_benchmark` (picks),
  ``apply_edits``: :func:`sdn3d.editing.apply.apply_edits`;
- ``scene_maps``: :func:`sdn3d.scene.maps.scene_maps` of the edited scene; ``generator``:
  :func:`sdn3d.editing.render.render_maps` (the textural generator);
- ``total``: the sum (``compose='full'``, the paper's protocol: the generator's picture at the working size);
- ``compose='edited'`` (the default of ``sdn3d-edit``): the edit put into the input at its own resolution
  (``--input-size``, default Virtual KITTI's 1242x375: the source frame's RGB upscaled bilinearly to it, mapped
  to the working size by :func:`sdn3d.editing.inputs.fit_transform`): ``compose.source_maps`` (the unedited
  scene's maps, which the edit region compares against; ``sdn3d-edit`` computes them anyway for its
  reconstruction) and ``compose.blend`` (the generator appearance's ``draw``,
  :func:`sdn3d.editing.appearance.appearance_renderer`, i.e. :func:`sdn3d.editing.compose.compose_edit`: edited
  objects, edit region, feathered alpha, upsampling and blend); ``compose`` is their sum and ``total_edited`` =
  ``total`` + ``compose``.

Networks, with random weights unless checkpoints are given: ``demo`` and ``paper`` take the model
(and crop size) settings of ``conf/recipe/{geometric,textural}_{demo,paper}.yaml`` over ``conf/branch``;
``--geometric`` / ``--textural`` checkpoints replace the demo ones (their own hyper-parameters).
``--semantic`` also times the semantic branch's forward on the frame (not on the ``gt`` path: it is
what de-rendering an image without ground truth adds).

``--device cuda`` puts the networks and the mesh bank (so ``scene_maps``' rasterization) on the GPU;
every timed call ends with ``torch.cuda.synchronize``, so a stage's time includes its kernels. The
frame is still read and cropped on the CPU, as :func:`sdn3d.derender.derender` does.

The editing code alone is timed against its dense reference too (``reference``:
``sdn3d.reference.scene_maps.scene_maps_dense``, every object rasterized over the whole frame and composed
densely, and ``sdn3d.reference.editing.apply_edits_dense``, which always re-composes the observed objects to
find freed pixels), on the same scenes, with a check that both give identical results.

Every figure is the median (and min) over ``--repeats`` passes over ``--entries`` entries after one
warm-up pass, in milliseconds of wall time, with the process CPU time beside it (summed over threads:
on a shared, oversubscribed CPU the wall time also counts waiting for a core). The JSON records the
torch thread count, the load average before and after and the CPU count.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import torch
from omegaconf import OmegaConf

from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.frames import load_frame
from sdn3d.data.records import load_rgb
from sdn3d.data.scene_gt import ground_truth
from sdn3d.data.synth import BENCHMARK_NAME, SynthConfig, generate_dataset
from sdn3d.data.vkitti1 import read_frames
from sdn3d.derender import Models, derender
from sdn3d.editing.appearance import Appearance, appearance_renderer, render_maps
from sdn3d.editing.apply import apply_edits, ops_from_benchmark
from sdn3d.editing.compose import ComposeSettings
from sdn3d.editing.inputs import fit_transform
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.model import GeometricNet
from sdn3d.geometric.predict import GeometricPredictor, net_kwargs_from_hparams
from sdn3d.labels import class_list
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.meshes import MeshBank
from sdn3d.nets.pix2pixhd import TexturalSpec
from sdn3d.reference.editing import apply_edits_dense
from sdn3d.reference.scene_maps import scene_maps_dense
from sdn3d.scene.maps import scene_maps
from sdn3d.textural.renderer import TexturalRenderer

REPO = Path(__file__).resolve().parents[1]
STAGES = ("derender", "edit_ops", "apply_edits", "scene_maps", "generator")
COMPOSE_STAGES = ("compose.source_maps", "compose.blend")
TARGET_MS = 1000.0


def branch_model(branch: str, preset: str) -> tuple[dict[str, Any], dict[str, Any]]:
    """``(model, datamodule)`` settings of ``conf/branch/<branch>.yaml`` with ``conf/recipe/<branch>_<preset>.yaml``
    merged."""
    cfg = OmegaConf.merge({"data": {"classes": "vkitti", "image_size": [624, 192]}, "seed": 0,
                           "ablation": OmegaConf.load(REPO / "conf" / "ablation" / "full.yaml"),
                           "renderer": OmegaConf.load(REPO / "conf" / "renderer" / "default.yaml")},
                          OmegaConf.load(REPO / "conf" / "branch" / f"{branch}.yaml"))
    recipe = OmegaConf.load(REPO / "conf" / "recipe" / f"{branch}_{preset}.yaml")
    cfg = OmegaConf.merge(cfg, {k: v for k, v in recipe.items() if k in ("model", "datamodule")})
    return OmegaConf.to_container(cfg.model, resolve=True), OmegaConf.to_container(cfg.datamodule, resolve=True)


def _params(module: torch.nn.Module) -> int:
    return sum(p.numel() for p in module.parameters())


def build_models(preset: str, geometric: str | None, textural: str | None) -> tuple[Models, dict]:
    """The preset's branches (random weights), checkpoints where given; and how they were made."""
    info: dict[str, Any] = {}
    if geometric:
        loaded = Models.from_checkpoints(geometric=geometric)
        geo, crop, margin = loaded.geometric, loaded.crop_size, loaded.margin
        info["geometric"] = {"source": f"checkpoint {geometric}"}
    else:
        model, dm = branch_model("geometric", preset)
        geo = GeometricPredictor(GeometricNet(**net_kwargs_from_hparams(model)),
                                 AttributeEncoding(model["rotation"], model["distance"]))
        crop, margin = int(dm["crop_size"]), float(dm["margin"])
        info["geometric"] = {"source": f"random weights, conf/recipe/geometric_{preset}.yaml"}
    info["geometric"] |= {"params": _params(geo.net), "crop_size": crop}
    if textural:
        tex = TexturalRenderer.from_checkpoint(textural)
        info["textural"] = {"source": f"checkpoint {textural}"}
    else:
        model, _ = branch_model("textural", preset)
        tex = TexturalRenderer(TexturalSpec.from_mapping(model, num_classes=len(class_list("vkitti"))))
        info["textural"] = {"source": f"random weights, conf/recipe/textural_{preset}.yaml"}
    spec = tex.spec
    info["textural"] |= {"generator_params": _params(tex.generator), "encoder_params": _params(tex.encoder),
                         "ngf": spec.ngf, "n_downsampling": spec.n_downsampling, "n_blocks": spec.n_blocks,
                         "nef": spec.nef, "n_downsampling_encoder": spec.n_downsampling_encoder}
    return Models(None, geo, tex, crop_size=crop, margin=margin), info


def _semantic_forward(preset: str, image: torch.Tensor, repeats: int, device: torch.device) -> dict:
    from sdn3d.nets.drn import DRNSeg
    from sdn3d.semantic.predict import SemanticPredictor

    model, _ = branch_model("semantic", preset)
    net = DRNSeg(14, arch=model["arch"], instance_head=model["instance_head"], head_channels=model["head_channels"],
                 pretrained=None, **({"channels": model["channels"]} if model.get("channels") else {}))
    predictor = SemanticPredictor(net, "vkitti").to(device)
    predictor(image)
    wall, cpu = [], []
    for _ in range(repeats):
        w, c = time.perf_counter(), time.process_time()
        predictor(image)
        if device.type == "cuda":
            torch.cuda.synchronize()
        wall.append(1000 * (time.perf_counter() - w))
        cpu.append(1000 * (time.process_time() - c))
    return {"arch": model["arch"], "params": _params(net), "input": list(image.shape[-2:][::-1]),
            **_summary(wall, cpu)}


class _Clock:
    """Wall and process CPU milliseconds per named stage; ``wrap`` times a method inside another stage."""

    def __init__(self, device: torch.device | None = None) -> None:
        self.wall: dict[str, list[float]] = {}
        self.cpu: dict[str, list[float]] = {}
        self.on = False
        self.cuda = device is not None and device.type == "cuda"

    def time(self, name: str, fn: Callable, *args, **kwargs):
        w, c = time.perf_counter(), time.process_time()
        out = fn(*args, **kwargs)
        if self.cuda:  # kernels are asynchronous: count them in the stage that launched them
            torch.cuda.synchronize()
        if self.on:
            self.wall.setdefault(name, []).append(1000 * (time.perf_counter() - w))
            self.cpu.setdefault(name, []).append(1000 * (time.process_time() - c))
        return out

    def wrap(self, obj: Any, method: str, name: str) -> None:
        inner = getattr(obj, method)
        object.__setattr__(obj, method, lambda *a, **k: self.time(name, inner, *a, **k))


def _summary(wall: list[float], cpu: list[float]) -> dict:
    return {"median_ms": round(statistics.median(wall), 2), "min_ms": round(min(wall), 2), "n": len(wall),
            "cpu_median_ms": round(statistics.median(cpu), 2)}


def _same_maps(a, b) -> bool:
    return all(torch.equal(getattr(a, k), getattr(b, k)) for k in a.as_dict())


def _derender_gt(frame: Any, record: Any, models: Models) -> Any:
    """:func:`derender` with ``proposals='gt'``: the frame's masks and semantics read from disk, then the branches."""
    gt = ground_truth(record, (frame.intrinsics.width, frame.intrinsics.height))
    return derender(frame.image, frame.intrinsics, models, "gt", gt, min_pixels=64)


def run_preset(models: Models, cases: list, repeats: int, reference: bool, device: torch.device | None = None) -> dict:
    """Time every stage over ``repeats`` passes of ``cases`` (after one warm-up pass)."""
    device = device or torch.device("cpu")
    clock = _Clock(device)
    bank = MeshBank.templates().to(device) if device.type != "cpu" else None
    clock.wrap(models.geometric, "predict", "derender.geometric")
    clock.wrap(models.textural, "encode", "derender.encoder")
    bins = models.textural.spec.pose_bins
    identical = True
    objects: list[dict[str, int]] = []
    renderer = appearance_renderer(Appearance.GENERATOR, compose=ComposeSettings("edited"), textural=models.textural)
    for rep in range(repeats + 1):
        clock.on = rep > 0
        for entry, record, frame, original, transform in cases:
            scene = clock.time("derender", _derender_gt, frame, record, models)
            if rep == 0:
                objects.append({"objects": len(scene.objects), "with_geometry": int(scene.objects.has_geometry.sum())})
            ops = clock.time("edit_ops", ops_from_benchmark, entry, scene, strict=False)
            edited = clock.time("apply_edits", apply_edits, scene, ops)
            maps = clock.time("scene_maps", scene_maps, edited, bank, num_bins=bins)
            generated = clock.time("generator", render_maps, maps, models.textural)
            state = renderer.prepare(original, transform, scene, bank)
            clock.time("compose.source_maps", state.source_maps, bins)
            # The source maps made above: draw is the edit region and the blend (its Drawn.times['compose_ms']).
            clock.time("compose.blend", renderer.draw, state, edited, ops, (maps, generated))
            if reference:
                old_edit = clock.time("reference.apply_edits", apply_edits_dense, scene, ops)
                old_maps = clock.time("reference.scene_maps", scene_maps_dense, edited, num_bins=bins)
                identical &= (old_edit == edited) and _same_maps(old_maps, maps)
    n = len(clock.wall["derender"])
    total_wall = [sum(clock.wall[s][i] for s in STAGES) for i in range(n)]
    total_cpu = [sum(clock.cpu[s][i] for s in STAGES) for i in range(n)]
    compose_wall = [sum(clock.wall[s][i] for s in COMPOSE_STAGES) for i in range(n)]
    compose_cpu = [sum(clock.cpu[s][i] for s in COMPOSE_STAGES) for i in range(n)]
    out = {"stages": {k: _summary(clock.wall[k], clock.cpu[k]) for k in clock.wall},
           "total": _summary(total_wall, total_cpu), "compose": _summary(compose_wall, compose_cpu),
           "total_edited": _summary([a + b for a, b in zip(total_wall, compose_wall, strict=True)],
                                    [a + b for a, b in zip(total_cpu, compose_cpu, strict=True)])}
    out["scenes"] = objects
    if reference:
        out["reference_identical"] = bool(identical)
    out["meets_target"] = out["total"]["median_ms"] < TARGET_MS
    # With one thread, the CPU time is about the wall time on an idle core (wall also counts waiting for one).
    out["meets_target_cpu_time"] = out["total"]["cpu_median_ms"] < TARGET_MS
    return out


def load_cases(root: Path, size: tuple[int, int], count: int, input_size: tuple[int, int]) -> list:
    """``(entry, record, frame at size, original (3, H_in, W_in) uint8, input -> working transform)`` per entry;
    the original is the frame's RGB resized to ``input_size`` (bilinear)."""
    from PIL import Image

    records = index_records(read_frames(root))
    entries = [e for e in load_edit_benchmark(root / BENCHMARK_NAME) if e.operations][:count]
    if not entries:
        raise SystemExit(f"{root / BENCHMARK_NAME} has no edit entries")
    cases = []
    for entry in entries:
        record = records[(entry.world, entry.variation, entry.source_frame)]
        rgb = np.asarray(Image.fromarray(load_rgb(record)).resize(input_size, Image.BILINEAR))
        original = torch.from_numpy(np.ascontiguousarray(rgb)).permute(2, 0, 1)
        cases.append((entry, record, load_frame(record, size, semantic=False, instances=False), original,
                      fit_transform(size, input_size)))
    return cases


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--threads", type=int, nargs="+", default=[1])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--entries", type=int, default=3, help="benchmark entries (edits) per pass")
    p.add_argument("--cars", type=int, default=11, help="cars placed per synthetic frame")
    p.add_argument("--size", type=int, nargs=2, default=(624, 192), metavar=("W", "H"))
    p.add_argument("--presets", nargs="+", default=["demo", "paper"], choices=["demo", "paper"])
    p.add_argument("--geometric", default=None, help="geometric checkpoint (replaces the demo net)")
    p.add_argument("--textural", default=None, help="textural checkpoint (replaces the demo nets)")
    p.add_argument("--data", default=None, help="existing synthetic dataset root (default: generate one)")
    p.add_argument("--no-reference", action="store_true", help="skip the dense reference editing code")
    p.add_argument("--semantic", action="store_true", help="also time the semantic branch's forward")
    p.add_argument("--out", default=None, help="also write the JSON here")
    p.add_argument("--device", default="cpu", help="cpu | cuda (networks and mesh bank)")
    p.add_argument("--input-size", type=int, nargs=2, default=(1242, 375), metavar=("W", "H"),
                   help="resolution of the input picture compose='edited' writes (the frame's RGB resized to it)")
    args = p.parse_args(argv)
    device = torch.device(args.device)
    if device.type == "cuda" and not torch.cuda.is_available():
        raise SystemExit("--device cuda but CUDA is not available")
    size = (int(args.size[0]), int(args.size[1]))
    torch.manual_seed(0)
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(args.data) if args.data else generate_dataset(SynthConfig(
            output_dir=str(Path(tmp) / "synth"), seed=0, image_size=size, frames_per_sequence=2,
            cars_per_frame=(args.cars, args.cars), edit_pairs=max(args.entries, 1)))
        input_size = (int(args.input_size[0]), int(args.input_size[1]))
        cases = load_cases(root, size, args.entries, input_size)
        result: dict[str, Any] = {
            "what": "per-edit latency (derender + edit_ops + apply_edits + scene_maps + generator; compose='edited' "
                    "adds compose.source_maps + compose.blend at input_size), ms",
            "size": list(size), "input_size": list(input_size), "input_transform": cases[0][4].to_dict(),
            "entries": [f"{c[0].world}/{c[0].variation} {c[0].source_frame}->{c[0].target_frame} "
                        f"{[o.kind for o in c[0].operations]}" for c in cases],
            "repeats": args.repeats, "statistic": "median (min) over repeats x entries after one warm-up pass",
            "cpu_count": os.cpu_count(), "torch": torch.__version__, "device": str(device),
            "gpu": torch.cuda.get_device_name(device) if device.type == "cuda" else None,
            "target_ms": TARGET_MS, "runs": []}
        for threads in args.threads:
            torch.set_num_threads(threads)
            for preset in args.presets:
                load_before = os.getloadavg()
                ckpt = preset == "demo"
                models, info = build_models(preset, args.geometric if ckpt else None, args.textural if ckpt else None)
                models.geometric.net.to(device)
                models.textural.to(device)
                run = {"preset": preset, "threads": torch.get_num_threads(), "device": str(device), "nets": info,
                       **run_preset(models, cases, args.repeats, not args.no_reference, device)}
                if args.semantic:
                    run["semantic_forward"] = _semantic_forward(preset, cases[0][2].image, args.repeats, device)
                run["loadavg_before"] = [round(v, 2) for v in load_before]
                run["loadavg_after"] = [round(v, 2) for v in os.getloadavg()]
                result["runs"].append(run)
                print(json.dumps({"preset": preset, "threads": threads, "total": run["total"],
                                  "compose": run["compose"], "total_edited": run["total_edited"]}), file=sys.stderr)
    text = json.dumps(result, indent=2)
    print(text)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(text + "\n")


if __name__ == "__main__":
    main()
