# ruff: noqa: INP001, E501
"""oracle_pose.py BENCH_ARGS...: sdn3d-bench with the predicted row's fitted poses swapped for ground truth (an oracle
for diagnosis). Each predicted object with geometry whose mask overlaps a ground-truth vehicle at IoU >= 0.3 (the
best one) takes that vehicle's fields named by ORACLE: geo = template, FFD (zero), dimensions, yaw and location;
yaw = the yaw alone; loc = the location alone; shape = template, FFD and dimensions; noyaw = all of geo but the yaw;
gtfit = all of geo, but from the test-time fit of the ground-truth masks (the oracle row's poses), not the truth. The masks stay the semantic branch's. Everything else is `python -m sdn3d.cli.bench`."""
import dataclasses
import os
import sys

import torch

import sdn3d.evaluation.edit_benchmark as eb
from sdn3d.cli.bench import main
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.proposals import Proposals

MODE = os.environ["ORACLE"]
FIELDS = {"geo": ("template_id", "phi", "dims", "ry", "location"), "yaw": ("ry",), "loc": ("location",),
          "shape": ("template_id", "phi", "dims"), "noyaw": ("template_id", "phi", "dims", "location"),
          "gtfit": ("template_id", "phi", "dims", "ry", "location")}
_original = eb._source_scene
COUNT = {"objects": 0, "swapped": 0}


def _swapped(image, intrinsics, record, models, settings):
    scene = _original(image, intrinsics, record, models, settings)
    if settings.scene is eb.Scene.ORACLE:
        return scene
    if MODE == "gtfit":
        truth = _original(image, intrinsics, record, models, dataclasses.replace(settings, proposals=Proposals.GT)).objects
    else:
        truth = scene_from_frame(record, settings.image_size, scene.objects.code.shape[1]).objects
    obj = scene.objects
    geo_p, geo_t = obj.has_geometry, truth.has_geometry & truth.mask.flatten(1).any(1)
    if not bool(geo_p.any()) or not bool(geo_t.any()):
        return scene
    pm, tm = obj.mask.flatten(1).float(), truth.mask.flatten(1).float()
    inter = pm @ tm.T
    iou = inter / (pm.sum(1, keepdim=True) + tm.sum(1)[None] - inter).clamp_min(1)
    iou[~geo_p] = 0
    iou[:, ~geo_t] = 0
    best, idx = iou.max(1)
    take = best >= 0.3
    COUNT["objects"] += int(geo_p.sum())
    COUNT["swapped"] += int(take.sum())
    fields = {}
    for name in FIELDS[MODE]:
        value = getattr(obj, name).clone()
        value[take] = getattr(truth, name)[idx[take]].to(value.dtype)
        fields[name] = value
    return scene.replace(objects=obj.replace(**fields))


eb._source_scene = _swapped
torch.set_num_threads(1)
rc = main(sys.argv[1:])
print(f"oracle_pose {MODE}: swapped {COUNT['swapped']} of {COUNT['objects']} predicted objects with geometry",
      file=sys.stderr)
sys.exit(rc)
