# ruff: noqa: E501
"""variants.py TREE OUT.json SOURCES VARIANT[,VARIANT...]: the counterfactual turns of TREE (sdn3d-synth's exact
pairs), photo appearance fill rays only, each pair drawn once per VARIANT of the normals the unseen part lookup
compares (transfer._part_normals), in one process: the source scene is made once per target car and source.

SOURCES: comma list of oracle (ground-truth geometry) / semantic (predicted; the session 11 demo's branches, the
bench's default test-time fit). VARIANTS (all patch transfer._part_normals, i.e. which points of the body use the
mesh's smooth normals; glass, tyres, lamps and plates keep flat ones):
  flat          main's behaviour (no smoothing)
  smooth        session 12's rejected rule (every body point, queries and examples: vertex normals over all faces)
  crease<D>     the branch's rule with SMOOTH_NORMAL_CREASE_DEG = D (corner normals blend faces within D degrees)
  ang<D>        body points whose smooth normal is within D degrees of the flat one
  side<C>       body points whose flat normal's component along the car's lateral axis is at least C
  q:<V> / e:<V> rule V on the unseen queries (q) or on the examples (e) alone, flat on the other
  branch        the branch's own _part_normals, unpatched
  V+wheels      V, and the transfer skips input pixels whose part the dark cars' wheel registration changed
                (PhotoSource.registered_parts, the branch's); without +wheels the templates' own part map (main's)
Writes OUT.json: {"pairs": [{key, source, bin, metrics: {variant: {car: {psnr, l1, flat}}}}]} (the bench's form,
one method per variant)."""

from __future__ import annotations

import json
import math
import sys
import time

import torch

from sdn3d.cli._config import compose_config
from sdn3d.cli.bench import _proposal_fit
from sdn3d.data.counterfactual import load_pairs
from sdn3d.data.vkitti1 import read_frames
from sdn3d.derender import Models
from sdn3d.editing.photo import transfer
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.evaluation import counterfactual as cf
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.meshes.parts import Part

BRANCH_PART_NORMALS = transfer._part_normals
RUNS = "/tmp/s11data/demo/out/runs"


def lateral_axis(r, mesh: torch.Tensor) -> torch.Tensor:
    """``(P, 3)`` each point's car's lateral axis (camera frame): the smaller principal axis of its mesh's vertices
    on the ground plane (x, z)."""
    out = torch.zeros(len(mesh), 3, dtype=torch.float64)
    for m in mesh.unique().tolist():
        v = r.verts[m][:, [0, 2]].double()
        v = v - v.mean(0)
        _, vecs = torch.linalg.eigh(v.T @ v)
        ax = vecs[:, 0]  # smallest variance: across the car
        out[mesh == m] = torch.tensor([ax[0], 0.0, ax[1]], dtype=torch.float64)
    return out


def rule(name: str):
    """``keep(r, mesh, flat, smooth) -> (P,) bool``: where the smooth normal is used (session 12's vertex normals)."""
    if name == "smooth":
        return lambda r, mesh, flat, smooth: torch.ones(len(flat), dtype=torch.bool)
    if name.startswith("ang"):
        cos = math.cos(math.radians(float(name[3:])))
        return lambda r, mesh, flat, smooth: (flat * smooth).sum(-1) >= cos
    if name.startswith("side"):
        c = float(name[4:])
        return lambda r, mesh, flat, smooth: (flat * lateral_axis(r, mesh)).sum(-1).abs() >= c
    raise ValueError(name)


STATE = {"examples": False, "variant": "flat", "wheels": False}
ORIGINAL_REGISTERED = transfer.PhotoSource.registered_parts


def patched_registered(self):
    return ORIGINAL_REGISTERED(self) if STATE["wheels"] else self.parts


def patched_part_normals(r, pix, flat, parts):
    v = STATE["variant"]
    if v.startswith(("q:", "e:")):
        applies = (v[0] == "e") == STATE["examples"]
        v = v[2:] if applies else "flat"
    if v == "branch":
        return BRANCH_PART_NORMALS(r, pix, flat, parts)
    if v == "flat":
        return flat
    if v.startswith("crease"):
        old = transfer.SMOOTH_NORMAL_CREASE_DEG
        transfer.SMOOTH_NORMAL_CREASE_DEG = float(v[6:])
        try:
            return BRANCH_PART_NORMALS(r, pix, flat, parts)
        finally:
            transfer.SMOOTH_NORMAL_CREASE_DEG = old
    body = parts.long() == int(Part.BODY)
    if not bool(body.any()):
        return flat
    out = flat.clone()
    smooth = transfer._smooth_normals(r, pix[body], flat[body], 180.0)
    keep = rule(v)(r, r.frags.pix_to_mesh.view(-1)[pix[body]], flat[body], smooth)
    out[body] = torch.where(keep[:, None], smooth, flat[body])
    return out


ORIGINAL_EXAMPLES = transfer._part_examples


def patched_examples(*args, **kwargs):
    STATE["examples"] = True
    try:
        return ORIGINAL_EXAMPLES(*args, **kwargs)
    finally:
        STATE["examples"] = False


class VariantRenderer:
    def __init__(self, base, variant: str):
        self.base, self.variant = base, variant

    def prepare(self, *args, **kwargs):
        return self.base.prepare(*args, **kwargs)

    def draw(self, *args, **kwargs):
        STATE["variant"] = self.variant.removesuffix("+wheels")
        STATE["wheels"] = self.variant.endswith("+wheels")
        return self.base.draw(*args, **kwargs)


def main() -> None:
    tree, out, sources, variants = sys.argv[1], sys.argv[2], sys.argv[3].split(","), sys.argv[4].split(",")
    torch.set_num_threads(1)
    transfer._part_normals = patched_part_normals
    transfer._part_examples = patched_examples
    transfer.PhotoSource.registered_parts = patched_registered
    names = tuple(f"photo:rays|{v}" for v in variants)
    base_renderers = cf._renderers

    def renderers(_names, settings, models):
        base = base_renderers(("photo:rays",), settings, models)["photo:rays"]
        return {n: VariantRenderer(base, n.split("|", 1)[1]) for n in names}

    cf._renderers = renderers
    cf.methods = lambda settings, has_generator: names
    cfg = compose_config([], "bench")
    models = None
    if "semantic" in sources:
        models = Models.from_checkpoints(f"{RUNS}/semantic/checkpoints/inference.pt",
                                         f"{RUNS}/geometric/checkpoints/inference.pt", None, map_location="cpu")
    settings = cf.CounterfactualSettings(sources=tuple(sources), fills=("rays",), generator=False, baselines=(),
                                         photo=PhotoSettings.from_mapping({k: v for k, v in cfg.photo.items() if k != "fill"}),
                                         min_pixels=int(cfg.geometric.min_pixels), fit=_proposal_fit(cfg), kinds=("turn",))
    index = load_pairs(tree)
    t0 = time.time()
    results = cf.run_counterfactual(index, index_records(read_frames(tree)), models, settings,
                                    lambda i, n, rows: print(f"[{i}/{n}] {time.time() - t0:.0f}s", flush=True))
    json.dump({"tree": tree, "variants": variants, "sources": sources, "wall_s": time.time() - t0,
               "pairs": [r.to_json() for r in results]}, open(out, "w"))


if __name__ == "__main__":
    main()
