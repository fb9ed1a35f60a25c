# ruff: noqa: E501
# (session 12 realframe/probe.py, copied by session 21 cover: the repository root one folder deeper)
"""Real frame probe: the frame of tests/data de-rendered once with a box per car (the demo weights), then every edit of
the real strip (turned 45/90/180, recoloured blue, deleted) drawn by one EditSession; saves each edited picture, its
source and part maps as .npz, and the de-rendered scene (torch.save) for reuse.

    python probe.py RUN_DIR OUT_DIR [OVERRIDE ...]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import yaml

REPO = Path(__file__).resolve().parents[6]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
EDITS = [("turned 45", {"op": "rotate", "ry_deg": 45}), ("turned 90", {"op": "rotate", "ry_deg": 90}),
         ("turned 180", {"op": "rotate", "ry_deg": 180}), ("recoloured blue", {"op": "recolor", "color": "blue"}),
         ("deleted", {"op": "delete"})]


def main() -> int:
    import dataclasses

    from PIL import Image

    from sdn3d.cli._config import compose_config
    from sdn3d.cli.edit import box_fit_for_input, load_models, open_input, resolve_checkpoints
    from sdn3d.editing.session import EditSession
    from sdn3d.editing.settings import appearance_settings, compose_settings, session_settings
    from sdn3d.editing.spec import load_edit_spec

    run, out, overrides = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3:]
    only = [o.split("=", 1)[1] for o in overrides if o.startswith("only=")]
    overrides = [o for o in overrides if not o.startswith("only=")]
    out.mkdir(parents=True, exist_ok=True)
    cfg = compose_config([f"input.image={FRAME}", f"run={run}", "proposals=boxes", "threads=1", *overrides], "edit")
    import torch
    torch.set_num_threads(1)
    checkpoints = resolve_checkpoints(cfg, None)
    models, bank = load_models(cfg, checkpoints)
    appearance, photo = appearance_settings(cfg)
    settings = session_settings(cfg, checkpoints, compose_settings(cfg), appearance, photo)
    settings = dataclasses.replace(settings, box_fit=box_fit_for_input(cfg, settings.box_fit))
    session = EditSession(models, bank, settings)
    inp, _ = open_input(cfg)
    for iid in (12001, 12002):
        for title, op in EDITS:
            name = f"{iid}_{title.replace(' ', '_')}"
            if only and not any(o in name for o in only):
                continue
            spec_file = out / f"spec_{name}.yaml"
            spec_file.write_text(yaml.safe_dump({"objects": BOXES, "ops": [{**op, "id": iid}]}))
            spec = load_edit_spec(str(spec_file), 0, None)
            t = time.perf_counter()
            derendered = session.derender(inp, spec)
            ops, edited_scene = session.resolve(derendered, spec)
            drawn = session.renderer.draw(derendered.source, edited_scene, ops, None)
            dt = time.perf_counter() - t
            res = drawn.photo
            edited = res.image.permute(1, 2, 0).numpy()
            Image.fromarray(edited).save(out / f"{name}.png")
            np.savez_compressed(out / f"{name}.npz", edited=edited, source=res.source.numpy(),
                                parts=res.parts.numpy() if res.parts is not None else np.zeros(1))
            print(name, f"{dt:.1f}s", res.summary().get("objects", {}).get(iid, res.summary().get("objects", {}).get(str(iid))), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
