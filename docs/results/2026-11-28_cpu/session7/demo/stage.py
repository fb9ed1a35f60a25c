# ruff: noqa: E402, E501, E701, E702
"""Run one stage of sdn3d-demo alone on an existing demo run (its data and trained runs): bench (proposal recall +
benchmark) or edits, as cli/demo.py calls them. Usage: python stage.py bench|edits DEMO_DIR OUT_DIR"""
import json
import sys
import time
from pathlib import Path

import torch

from sdn3d.cli import demo
from sdn3d.cli._config import compose_config

stage, src, out = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
cfg = compose_config([f"output_dir={out}", f"data_dir={src / 'data'}"], "demo")
torch.set_num_threads(int(cfg.threads))
summary = json.loads((src / "summary.json").read_text())
ckpts = {b: demo._checkpoint(s) for b, s in summary["training"].items()}
root = Path(cfg.data_dir)
t0 = time.perf_counter()
if stage == "bench":
    res = {"proposal_recall": demo.run_proposal_recall(cfg, root, ckpts)}
    t1 = time.perf_counter()
    bench = demo.run_bench(cfg, root, ckpts, out / "bench")
    res["bench"] = {"summary": bench["summary"]}
    res["recall_s"] = t1 - t0
else:
    res = {"edits": demo.run_edits(cfg, root, ckpts, out / "edits")}
res["stage_s"] = time.perf_counter() - t0
out.mkdir(parents=True, exist_ok=True)
(out / f"{stage}.json").write_text(json.dumps(res, indent=1, sort_keys=True, default=str))
print(f"{stage}: {res['stage_s']:.1f} s")
