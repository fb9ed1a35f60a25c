# ruff: noqa: E402, E501, E702
"""real_templates.py OUT: the real frame of tests/data de-rendered as session 12 realframe's probe.py does (one
EditSession, session 11's demo weights, session 4's boxes, the edit defaults, proposals=boxes): each boxed car's
fitted template, size and yaw with this tree's code, for a look (never tuned on)."""
import dataclasses
import sys
from pathlib import Path

import torch
import yaml

from sdn3d.cli._config import compose_config
from sdn3d.cli.edit import box_fit_for_input, load_models, open_input, resolve_checkpoints
from sdn3d.editing.session import EditSession
from sdn3d.editing.settings import appearance_settings, compose_settings, session_settings
from sdn3d.editing.spec import load_edit_spec
from sdn3d.meshes.templates import TEMPLATE_NAMES

FRAME = "/work/main/tests/data/0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
out = Path(sys.argv[1]); out.mkdir(parents=True, exist_ok=True)
cfg = compose_config([f"input.image={FRAME}", "run=/tmp/s11data/demo/out/runs", "proposals=boxes", "threads=1"], "edit")
torch.set_num_threads(1)
ck = resolve_checkpoints(cfg, None)
models, bank = load_models(cfg, ck)
ap, ph = appearance_settings(cfg)
st = session_settings(cfg, ck, compose_settings(cfg), ap, ph)
st = dataclasses.replace(st, box_fit=box_fit_for_input(cfg, st.box_fit))
inp, _ = open_input(cfg)
(out / "spec.yaml").write_text(yaml.safe_dump({"objects": BOXES, "ops": [{"op": "rotate", "ry_deg": 90, "id": 12001}]}))
scene = EditSession(models, bank, st).derender(inp, load_edit_spec(str(out / "spec.yaml"), 0, None)).source.scene
o = scene.objects
for iid, name in ((12001, "red car"), (12002, "black car")):
    i = int((o.instance_id == iid).nonzero()[0, 0])
    print(f"{name} ({iid}): {TEMPLATE_NAMES[int(o.template_id[i])]}, dims {[round(float(v), 2) for v in o.dims[i]]}, "
          f"ry {float(o.ry[i]):+.3f}")
