# ruff: noqa: E402, E501, E701, E702
"""real_probe.py: the real frame of tests/data with both cars boxed (session 4's boxes, session 11's demo weights, the
edit defaults, run in /tmp/s18data/tierule/real): each car's template belief (the geometric branch's softmax) and its
box fit again under several FitSettings.template_belief_reg (this tree's code). Looked at, never tuned on."""
import dataclasses
import os
from pathlib import Path

import torch
import yaml

import sdn3d.geometric.fit as gf
from sdn3d.cli._config import compose_config
from sdn3d.cli.edit import box_fit_for_input, load_models, open_input, resolve_checkpoints
from sdn3d.editing.session import EditSession
from sdn3d.editing.settings import appearance_settings, compose_settings, session_settings
from sdn3d.editing.spec import load_edit_spec
from sdn3d.meshes.templates import TEMPLATE_NAMES

FRAME = "/work/main/tests/data/0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
os.chdir("/tmp/s18data/tierule/real")
cfg = compose_config([f"input.image={FRAME}", "run=/tmp/s11data/demo/out/runs", "proposals=boxes", "threads=1"], "edit")
torch.set_num_threads(1)
ck = resolve_checkpoints(cfg, None); models, bank = load_models(cfg, ck)
ap, ph = appearance_settings(cfg)
st = session_settings(cfg, ck, compose_settings(cfg), ap, ph)
st = dataclasses.replace(st, box_fit=box_fit_for_input(cfg, st.box_fit))
inp, _ = open_input(cfg)
original, seen = gf.fit_many, {}


def spy(requests, intr, **kw):
    seen.update(requests=requests, intr=intr, kw=kw)
    return original(requests, intr, **kw)


gf.fit_many = spy
Path("spec.yaml").write_text(yaml.safe_dump({"objects": BOXES, "ops": [{"op": "rotate", "ry_deg": 90, "id": 12001}]}))
EditSession(models, bank, st).derender(inp, load_edit_spec("spec.yaml", 0, None))
(r,) = seen["requests"]
for i, name in enumerate(("red car (12001)", "black car (12002)")):
    p = r.template_belief[i]
    print(f"{name}: belief " + ", ".join(f"{TEMPLATE_NAMES[t]} {float(p[t]):.4f}" for t in range(len(p))) +
          f"; start template {TEMPLATE_NAMES[int(r.start_template[i])]}")
for reg in (0.0, 0.01, 0.03, 0.1, 0.3, 1.0):
    (o,) = original([r], seen["intr"], settings=dataclasses.replace(seen["kw"]["settings"], template_belief_reg=reg))
    print(f"reg {reg}: " + "; ".join(f"{TEMPLATE_NAMES[int(o.template[i])]} ry {float(o.ry[i]):+.3f} {o.hypothesis_name(i)} loss {float(o.loss[i]):.4f}" for i in range(len(o.template))))
