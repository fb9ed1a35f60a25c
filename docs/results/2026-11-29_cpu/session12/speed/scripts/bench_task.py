# ruff: noqa
"""bench_task.py OUT STEPS PROPOSALS: one demo lane task (the predicted row: recall,bench semantic; the edits: edits -)
on session 11's idle demo (data and checkpoints of /tmp/s11data/demo_final), threads 1, as the demo's lane runs it."""
import json, sys, time, os, resource
from pathlib import Path
from omegaconf import OmegaConf
from sdn3d.cli._config import compose_config
out, steps, proposals = Path(sys.argv[1]), sys.argv[2].split(","), sys.argv[3]
cfg = compose_config(["output_dir=" + str(out), "data_dir=/tmp/s11data/demo_final/data", "threads=1"], "demo")
R = "/tmp/s11data/demo_final/out/runs"
ckpts = {b: json.load(open(f"{R}/{b}/summary.json"))["best_ckpt"] for b in ("semantic", "geometric", "textural")}
spec = {"steps": steps, "config": OmegaConf.to_container(cfg, resolve=True), "data_root": "/tmp/s11data/demo_final/data",
        "checkpoints": ckpts, "output_dir": str(out), "proposals": None if proposals == "-" else proposals, "result": str(out / "result.pkl")}
out.mkdir(parents=True, exist_ok=True)
(out / "spec.json").write_text(json.dumps(spec))
from sdn3d.cli._demo_task import main
t = time.process_time(); w = time.perf_counter()
main([str(out / "spec.json")])
print(json.dumps({"steps": steps, "cpu_s": round(time.process_time() - t, 2), "wall_s": round(time.perf_counter() - w, 2), "load": os.getloadavg()}))
