"""A scene's objects as a person reads them: ids, classes, boxes and centres in an input image's pixels,
distances in metres, yaw in degrees (``sdn3d-edit list=true``)."""

from __future__ import annotations

import math
from typing import Any

from sdn3d.image_ops import mask_boxes
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.scene.code import SceneCode

__all__ = ["list_objects", "objects_table"]


def list_objects(scene: SceneCode, input_size: tuple[int, int], frame: Any = None) -> list[dict]:
    """The scene's objects as JSON-ready rows, positions in the pixels of an image of ``input_size (W, H)``.

    ``frame`` (a :class:`sdn3d.editing.frame.PixelFrame`, input -> working transform: scale then crop offset)
    maps the working pixels back to the input's; None: the scene is ``input_size`` resized.

    Each row: ``id``, ``class``, ``box`` ``[x0, y0, x1, y1]`` (half-open, the visible mask's box scaled out
    to whole input pixels; None without a mask), ``centre`` ``[u, v]`` (the projected 3D box centre, pixel
    centres at integers), ``distance_m`` (camera to 3D centre), ``yaw_deg`` (``ry``), ``template``; the last
    four (and ``xyz_m``, the 3D box centre in the camera frame) None for an object without geometry.
    """
    objects, intr = scene.objects, scene.intrinsics
    width, height = scene.image_size
    if frame is None:
        sx, sy, ox, oy = input_size[0] / width, input_size[1] / height, 0, 0
    else:
        sx, sy = 1 / frame.scale[0], 1 / frame.scale[1]
        ox, oy = frame.offset
    names = {c.id: c.name for c in scene.class_list}
    boxes = mask_boxes(objects.mask).tolist() if len(objects) else []
    rows = []
    for i in range(len(objects)):
        iid = int(objects.instance_id[i])
        row: dict[str, Any] = {"id": iid, "class": names.get(iid // INSTANCE_DIVISOR, str(iid // INSTANCE_DIVISOR)),
                               "box": None, "centre": None, "distance_m": None, "yaw_deg": None, "template": None,
                               "xyz_m": None}
        if bool(objects.has_mask[i]) and bool(objects.mask[i].any()):
            x0, y0, x1, y1 = boxes[i]
            row["box"] = [max(0, math.floor((x0 + ox) * sx)), max(0, math.floor((y0 + oy) * sy)),
                          min(input_size[0], math.ceil((x1 + ox) * sx)), min(input_size[1], math.ceil((y1 + oy) * sy))]
        tid = int(objects.template_id[i])
        if tid >= 0:
            c = objects.center[i].double().tolist()
            if c[2] > 0:  # in front of the camera: it projects
                u, v = intr.fx * c[0] / c[2] + intr.cx, intr.fy * c[1] / c[2] + intr.cy
                row["centre"] = [round((u + ox + 0.5) * sx - 0.5, 1), round((v + oy + 0.5) * sy - 0.5, 1)]
            row["distance_m"] = round(math.sqrt(sum(x * x for x in c)), 2)
            row["xyz_m"] = [round(x, 3) for x in c]
            row["yaw_deg"] = round(math.degrees(float(objects.ry[i])), 1)
            row["template"] = TEMPLATE_NAMES[tid] if tid < len(TEMPLATE_NAMES) else str(tid)
        rows.append(row)
    return rows


def objects_table(rows: list[dict]) -> str:
    """The rows of :func:`list_objects` as an aligned text table ('-': no value)."""
    def cell(value: Any) -> str:
        if value is None:
            return "-"
        if isinstance(value, list):
            return " ".join(f"{v:g}" if isinstance(v, float) else str(v) for v in value)
        return f"{value:g}" if isinstance(value, float) else str(value)

    head = ["id", "class", "box x0 y0 x1 y1", "centre u v", "distance m", "yaw deg", "template"]
    keys = ["id", "class", "box", "centre", "distance_m", "yaw_deg", "template"]
    if any("fit_iou" in r for r in rows):  # objects named by a box: how well the 3D fit matched its mask
        head, keys = head + ["fit IoU", "note"], keys + ["fit_iou", "note"]
        rows = [{**r, "note": ("poor fit" if r.get("poor_fit") else "from a box") if "fit_iou" in r else None}
                for r in rows]
    body = [[cell(r.get(k)) for k in keys] for r in rows]  # a proposal listed beside box objects has no fit_iou
    widths = [max(len(x) for x in col) for col in zip(head, *body, strict=True)]
    lines = ["  ".join(x.ljust(w) for x, w in zip(line, widths, strict=True)).rstrip() for line in [head, *body]]
    return "\n".join(lines if rows else ["(no objects found)"])
