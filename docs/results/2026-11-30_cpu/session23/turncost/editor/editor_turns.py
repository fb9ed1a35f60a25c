"""The editor's drag of a turn on the real frame: one EditSession (as sdn3d-app keeps per image), the tests/data frame
de-rendered once with README's two boxes (w0: session 21's demo weights), then car ID turned by 15, 30, ... 180
degrees, each drawn by the session's renderer (the same source state, its fills kept); prints the draw's wall and
process CPU ms of each turn as JSON. Run once per code with that code's src first on PYTHONPATH:

    PYTHONPATH=CODE/src OMP_NUM_THREADS=1 python editor_turns.py RUN_DIR ID [PROFILE] > out.json

(session 22 lead's editor_turns.py; session 23: with PROFILE, a CPU-time cProfile (time.process_time) of the turns
after the first, written to that file.)
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[6]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]


def main() -> int:
    import cProfile
    import dataclasses
    import tempfile

    import torch

    from sdn3d.cli._config import compose_config
    from sdn3d.cli.edit import box_fit_for_input, load_models, open_input, resolve_checkpoints
    from sdn3d.editing.session import EditSession
    from sdn3d.editing.settings import appearance_settings, compose_settings, session_settings
    from sdn3d.editing.spec import load_edit_spec

    run, iid = Path(sys.argv[1]), int(sys.argv[2])
    profile = cProfile.Profile(time.process_time) if len(sys.argv) > 3 else None
    cfg = compose_config([f"input.image={FRAME}", f"run={run}", "proposals=boxes", "threads=1"], "edit")
    torch.set_num_threads(1)
    checkpoints = resolve_checkpoints(cfg, None)
    models, bank = load_models(cfg, checkpoints)
    appearance, photo = appearance_settings(cfg)
    settings = session_settings(cfg, checkpoints, compose_settings(cfg), appearance, photo)
    settings = dataclasses.replace(settings, box_fit=box_fit_for_input(cfg, settings.box_fit))
    session = EditSession(models, bank, settings)
    inp, _ = open_input(cfg)
    turns = []
    with tempfile.TemporaryDirectory() as tmp:
        for deg in range(15, 181, 15):
            spec_file = Path(tmp) / "spec.yaml"
            op = {"op": "rotate", "id": iid, "ry_deg": deg}
            spec_file.write_text(yaml.safe_dump({"objects": BOXES, "ops": [op]}))
            spec = load_edit_spec(str(spec_file), 0, None)
            derendered = session.derender(inp, spec)  # cached after the first
            ops, edited_scene = session.resolve(derendered, spec)
            wall, cpu = time.perf_counter(), time.process_time()
            if profile is not None and deg > 15:
                profile.enable()
            session.renderer.draw(derendered.source, edited_scene, ops, None)
            if profile is not None:
                profile.disable()
            turns.append({"deg": deg, "wall_ms": 1e3 * (time.perf_counter() - wall),
                          "cpu_ms": 1e3 * (time.process_time() - cpu)})
    print(json.dumps({"id": iid, "turns": turns}))
    if profile is not None:
        profile.dump_stats(sys.argv[3])
    return 0


if __name__ == "__main__":
    sys.exit(main())
