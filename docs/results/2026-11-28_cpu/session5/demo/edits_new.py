# ruff: noqa: E402
"""The demo's example edits (sdn3d.cli.demo.run_edits, the demo's own settings) with the branches trained on the new
demo data (semantic and geometric, as the demo trains them; the textural generator of today's demo: the photo
appearance draws nothing with it), on the new demo data's test frames.

    python edits_new.py DATA SEMANTIC.ckpt GEOMETRIC.ckpt TEXTURAL.ckpt OUT
"""
import json
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(REPO / "src"))

from sdn3d.cli._config import compose_config
from sdn3d.cli.demo import run_edits

data, semantic, geometric, textural, out = sys.argv[1:6]
cfg = compose_config(["threads=1"], "demo")
t = time.time()
info = run_edits(cfg, Path(data), {"semantic": semantic, "geometric": geometric, "textural": textural}, Path(out))
info["wall_s"] = round(time.time() - t, 1)
print(json.dumps(info, indent=1, default=str))
