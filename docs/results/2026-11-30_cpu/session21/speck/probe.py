# ruff: noqa: E501
"""Real frame probe (session 12's realframe/probe.py, cut to this task's edits): the frame of tests/data de-rendered
with a box per car (README's boxes, proposals=boxes, the demo weights of RUN_DIR), then each car turned by 90 degrees
and deleted, drawn by one EditSession; saves each edited picture (.png) and its source and part maps (.npz), and
the de-rendered scene with each edited one (scenes.pt, for redraw.py).

    cd CODE_TREE && PYTHONPATH=CODE_TREE/src OMP_NUM_THREADS=1 nice -n 5 python probe.py RUN_DIR OUT_DIR [only=deleted]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import yaml

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
EDITS = [("turned 90", {"op": "rotate", "ry_deg": 90}), ("deleted", {"op": "delete"})]


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
    saved: dict = {}
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
            saved[name] = edited_scene
            drawn = session.renderer.draw(derendered.source, edited_scene, ops, None)
            dt = time.perf_counter() - t
            res = drawn.photo
            edited = res.image.permute(1, 2, 0).numpy()
            Image.fromarray(edited).save(out / f"{name}.png")
            np.savez_compressed(out / f"{name}.npz", edited=edited, source=res.source.numpy(),
                                parts=res.parts.numpy() if res.parts is not None else np.zeros(1))
            print(name, f"{dt:.1f}s", res.summary().get("objects", {}).get(iid, res.summary().get("objects", {}).get(str(iid))), flush=True)
    # For redraw.py: the same scene and edits drawn with other photo settings, without a de-render.
    torch.save({"scene": derendered.scene, "frame": derendered.input.frame, "edits": saved}, out / "scenes.pt")
    return 0


if __name__ == "__main__":
    sys.exit(main())
