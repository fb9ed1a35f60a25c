# ruff: noqa: INP001, E501, PLR0912, C901
"""swap_bench.py <sdn3d-bench overrides>: ``python -m sdn3d.cli.bench`` with the de-rendered source scenes changed
for a diagnosis (session 40, issue 40); every change is off unless its environment variable is set:

- ``SWAP=template,dims,ry,loc,phi`` (any of them): each fitted vehicle that the frame's ground truth also holds takes
  those fields from the ground truth (an oracle per field: the ladder of ``../ladder/``);
- ``FITOV=name=value,...``: the benchmark's ``FitSettings`` with these fields replaced (e.g. ``fine_steps=48``);
- ``HEIGHT=true``: the fit's camera height is the frame's true road plane (the median ground-truth vehicle's
  bottom-face ``y``; an oracle);
- ``SNAP=degrees``: after the fit, a vehicle whose fitted axis lies within that many degrees of the road's axis its
  fit was drawn towards (its record's ``road_axis_deg``) takes that axis, at the end it faces;
- ``LOG=file.json``: each fitted vehicle's fields beside the ground truth's (and its record's road axis), written at
  the end.

The oracle row (``scene=oracle``) is never changed. What changed goes to stderr at the end (``SWAP ... {...}``).
"""

import dataclasses
import json
import math
import os
import sys

import sdn3d.evaluation.edit_benchmark as EB
from sdn3d.cli.bench import main
from sdn3d.data.scene_gt import scene_from_frame

SWAP = [s for s in os.environ.get("SWAP", "").split(",") if s]
FITOV = os.environ.get("FITOV", "")
HEIGHT = os.environ.get("HEIGHT")
SNAP = float(os.environ.get("SNAP", "0"))
LOG = os.environ.get("LOG")
STATS: dict = {"objects": 0, "swapped": 0}
ROWS: list[dict] = []
_source_scene = EB._source_scene


def _fit_settings(settings, record, models):
    fit = settings.fit
    if FITOV:
        values = {}
        for item in FITOV.split(","):
            name, value = item.split("=")
            current = getattr(fit, name)
            values[name] = type(current)(float(value)) if isinstance(current, (int, float)) and not isinstance(current, bool) else value
        fit = dataclasses.replace(fit, **values)
    if HEIGHT:
        truth = scene_from_frame(record, settings.image_size, models.textural.spec.code_dim).objects
        ys = truth.location[truth.template_id >= 0, 1]
        if len(ys):
            fit = dataclasses.replace(fit, camera_height=float(ys.median()))
            STATS.setdefault("heights", []).append(round(float(ys.median()), 3))
    return dataclasses.replace(settings, fit=fit)


def _snap(ry, road_deg):
    """``ry`` moved onto the road's axis ``road_deg`` (the end nearest it) where it lies within SNAP degrees."""
    axis = math.radians(road_deg)
    end = axis if abs(math.atan2(math.sin(ry - axis), math.cos(ry - axis))) <= math.pi / 2 else axis + math.pi
    off = math.degrees(abs(math.atan2(math.sin(ry - end), math.cos(ry - end))))
    return (math.atan2(math.sin(end), math.cos(end)), True) if off < SNAP else (ry, False)


def _changed_scene(image, intrinsics, record, models, settings):
    if settings.scene is EB.Scene.ORACLE:
        return _source_scene(image, intrinsics, record, models, settings)
    if settings.fit is not None and (FITOV or HEIGHT):
        settings = _fit_settings(settings, record, models)
    scene = _source_scene(image, intrinsics, record, models, settings)
    if not (SWAP or LOG or SNAP):
        return scene
    truth = scene_from_frame(record, settings.image_size, models.textural.spec.code_dim).objects
    o = scene.objects
    at = {int(i): k for k, i in enumerate(truth.instance_id.tolist())}
    roads = {int(f["id"]): f.get("road_axis_deg") for f in scene.meta.get("fits", [])}
    template, dims, ry, location, phi = (o.template_id.clone(), o.dims.clone(), o.ry.clone(), o.location.clone(),
                                         o.phi.clone())
    for k, iid in enumerate(o.instance_id.tolist()):
        j = at.get(int(iid))
        STATS["objects"] += 1
        if j is None or int(o.template_id[k]) < 0 or int(truth.template_id[j]) < 0:
            continue
        if LOG:
            ROWS.append({"frame": str(getattr(record, "key", "")), "id": int(iid), "t": int(o.template_id[k]),
                         "gt_t": int(truth.template_id[j]), "ry": float(o.ry[k]), "gt_ry": float(truth.ry[j]),
                         "loc": o.location[k].tolist(), "gt_loc": truth.location[j].tolist(),
                         "dims": o.dims[k].tolist(), "gt_dims": truth.dims[j].tolist(), "px": int(o.mask[k].sum()),
                         "road": roads.get(int(iid))})
        if SNAP and roads.get(int(iid)) is not None:
            snapped, moved = _snap(float(ry[k]), roads[int(iid)])
            ry[k] = snapped
            STATS["snapped"] = STATS.get("snapped", 0) + int(moved)
        if not SWAP:
            continue
        STATS["swapped"] += 1
        if "template" in SWAP:
            template[k] = truth.template_id[j]
        if "dims" in SWAP:
            dims[k] = truth.dims[j].to(dims.dtype)
        if "ry" in SWAP:
            ry[k] = truth.ry[j].to(ry.dtype)
        if "loc" in SWAP:
            location[k] = truth.location[j].to(location.dtype)
        if "phi" in SWAP:
            phi[k] = truth.phi[j].to(phi.dtype)
    objects = dataclasses.replace(o, template_id=template, dims=dims, ry=ry, location=location, phi=phi)
    return dataclasses.replace(scene, objects=objects)


EB._source_scene = _changed_scene
code = main(sys.argv[1:])
print("SWAP", SWAP, {k: v for k, v in STATS.items() if k != "heights"}, file=sys.stderr)
if LOG:
    with open(LOG, "w") as f:
        json.dump(ROWS, f)
sys.exit(code)
