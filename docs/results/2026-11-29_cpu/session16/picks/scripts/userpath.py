# ruff: noqa: E501, E701, E702
"""userpath.py TREE CACHE SOURCE IDX[,IDX...]: what a user gets on the Table 1 entries IDX of a tree (their source
scenes as dbench.py cached them), under the code on PYTHONPATH: each modify written as an sdn3d-edit spec op
(`{op: modify, from, to, zoom, ry_rad}`, frame_size 1242x375) resolved by editing.spec.resolve_ops, as sdn3d-edit and
the editor resolve a spec; prints the id picked (with its mask's pixels, and the pixel's own object under the point:
the composed instance map) or the error a user reads, with sdn3d-edit's default pick_radius (16 working px) and with none."""
import glob
import sys

import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.edit_benchmark import load_edit_benchmark, scale_operation
from sdn3d.data.sources import read_source
from sdn3d.editing.apply import EditError
from sdn3d.editing.spec import parse_edit_spec, resolve_ops
from sdn3d.scene.maps import compose_instances

tree, cache, source, idx = sys.argv[1:5]
entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
records = {(r.world, r.variation, int(r.frame)): r for r in read_source(synth_data_source(tree))}
scenes = {}
for f in glob.glob(f"{cache}/*.pt"):
    s = torch.load(f, weights_only=False); scenes[(s.meta["source"], s.meta["proposals"])] = s
for i in [int(x) for x in idx.split(",")]:
    e = entries[i]
    s = scenes[(records[(e.world, e.variation, e.source_frame)].key, source)]
    under_map = compose_instances(s).cpu()
    px = dict(zip(s.objects.instance_id.tolist(), s.objects.mask.flatten(1).sum(1).tolist(), strict=True))
    for k, op in enumerate(e.operations):
        if op.kind != "modify": continue
        u, v = scale_operation(op, (1242, 375), (312, 96)).from_uv
        under = int(under_map[min(max(round(v), 0), 95), min(max(round(u), 0), 311)])
        raw = {"op": "modify", "from": list(op.from_uv), "zoom": op.zoom, "ry_rad": op.ry} | ({"to": list(op.to_uv)} if op.to_uv is not None else {})
        spec = parse_edit_spec({"frame_size": [1242, 375], "ops": [raw]})
        text = []
        for radius in (16.0, None):  # sdn3d-edit's default pick_radius, and none
            try:
                got = resolve_ops(spec, s, pick_radius=radius, strict=False)[0].instance_id
                text.append(f"[pick_radius {radius}] picks {got} ({int(px[got])} px)")
            except EditError as exc:
                text.append(f"[pick_radius {radius}] refused: {exc}")
        text = "; ".join(text)
        print(f"entry {i} op {k}: from {list(op.from_uv)} (working {u:.1f}, {v:.1f}); under the point: {under or 'no object'}"
              f"{f' ({int(px[under])} px, geometry {bool(s.objects.has_geometry[s.objects.index_of(under)])})' if under else ''}; sdn3d-edit {text}")
