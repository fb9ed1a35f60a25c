# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""scene_dump.py: the real frame of tests/data de-rendered with the red car boxed alone, then with both cars boxed
(session 11 demo weights): the fit requests and results of the red car, and its request fitted alone inside the
two-box run (run from /tmp/s17data/lead/light, main or the rows branch on PYTHONPATH)."""
import dataclasses, sys
from pathlib import Path
import yaml, torch
from sdn3d.cli._config import compose_config
from sdn3d.cli.edit import box_fit_for_input, load_models, open_input, resolve_checkpoints
from sdn3d.editing.session import EditSession
from sdn3d.editing.settings import appearance_settings, compose_settings, session_settings
from sdn3d.editing.spec import load_edit_spec
FRAME = "/work/main/tests/data/0006_30-deg-right_00043.png"
B = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
cfg = compose_config([f"input.image={FRAME}", "run=/tmp/s11data/demo/out/runs", "proposals=boxes", "threads=1"], "edit")
torch.set_num_threads(1)
ck = resolve_checkpoints(cfg, None); models, bank = load_models(cfg, ck)
ap, ph = appearance_settings(cfg)
st = session_settings(cfg, ck, compose_settings(cfg), ap, ph)
st = dataclasses.replace(st, box_fit=box_fit_for_input(cfg, st.box_fit))
inp, _ = open_input(cfg)
import sdn3d.geometric.fit as gf, sdn3d.box_objects as bo
_orig = gf.fit_many
def spy(requests, intr, **kw):
    for r in requests:
        print("  REQ n", len(r), "px", r.masks.flatten(1).sum(1).tolist(), "start_ry", r.start_ry.tolist() if r.start_ry is not None else None,
              "tmpl", r.start_template.tolist() if r.start_template is not None else None,
              "dims", r.start_dims.tolist() if r.start_dims is not None else None,
              "loc", r.start_location.tolist() if r.start_location is not None else None,
              "ignore px", r.ignore.flatten(1).sum(1).tolist() if r.ignore is not None else None)
        if r.yaw_belief is not None:
            import math
            ys = torch.linspace(-math.pi, math.pi, 9)[None].expand(len(r), 9)
            print("  belief", [[round(v, 2) for v in row] for row in r.yaw_belief(ys).tolist()])
    out = _orig(requests, intr, **kw)
    r = requests[0]
    if len(r) == 1:
        torch.save({"masks": r.masks, "boxes": r.boxes, "ignore": r.ignore, "classes": r.classes, "b": r.yaw_belief(torch.linspace(-3.14, 3.14, 721)[None])}, "/tmp/s17data/lead/light/req1.pt")
    if len(r) == 2:
        q = torch.load("/tmp/s17data/lead/light/req1.pt")
        print("  DIFF masks", (q["masks"][0] != r.masks[0]).sum().item(), "boxes", q["boxes"][0].tolist(), r.boxes[0].tolist(), "classes", q["classes"], r.classes,
              "belief maxdiff", (q["b"][0] - r.yaw_belief(torch.linspace(-3.14, 3.14, 721)[None].expand(2, 721))[0]).abs().max().item())
        import dataclasses as dc
        yb = r.yaw_belief
        one = dc.replace(r, masks=r.masks[:1], boxes=r.boxes[:1], ignore=r.ignore[:1], start_ry=r.start_ry[:1], start_dims=r.start_dims[:1],
                         start_template=r.start_template[:1], start_location=r.start_location[:1],
                         yaw_belief=lambda ry: yb(torch.cat([ry, ry]))[:1], classes=r.classes[:1] if r.classes else None)
        o1 = _orig([one], intr, **kw)[0]
        print("  ROW0 ALONE tmpl", o1.template.tolist(), "ry", o1.ry.tolist(), "hyp", o1.hypothesis.tolist(), "loss", o1.loss.tolist(), "height", o1.camera_height, out[0].camera_height)
        print("  settings", kw)
    for o in out:
        print("  RES tmpl", o.template.tolist(), "ry", o.ry.tolist(), "hyp", o.hypothesis.tolist(), "loss", o.loss.tolist(), "iou", o.iou.tolist())
    return out
gf.fit_many = spy
for boxes in (B[:1], B):
    s = EditSession(models, bank, st)
    f = Path("spec.yaml"); f.write_text(yaml.safe_dump({"objects": boxes, "ops": [{"op": "rotate", "ry_deg": 90, "id": 12001}]}))
    d = s.derender(inp, load_edit_spec(str(f), 0, None))
    o = d.scene.objects
    print(len(boxes), "boxes: template", o.template_id.tolist(), "dims", o.dims.tolist(), "ry", o.ry.tolist(), "loc", o.location.tolist(), "mask px", o.mask.flatten(1).sum(1).tolist())
    print("  attrs:", [a for a in dir(d) if not a.startswith("_")])
    print("  boxes:", d.boxes, "warnings", d.warnings)
    for a in ():
        if hasattr(d, a): print("  ", a, getattr(d, a))
    import numpy as np
    np.save(f"mask_{len(boxes)}.npy", o.mask[0].numpy())
