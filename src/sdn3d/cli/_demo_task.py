"""One of ``sdn3d-demo``'s lane tasks after training, in its own process (``python -m sdn3d.cli._demo_task SPEC``).

``SPEC`` (JSON, written by :func:`sdn3d.cli.demo.lane_tasks`): ``steps`` (of ``recall``, ``bench``, ``edits``, run
in the order listed), ``config`` (the demo's resolved config, ``threads`` already the task's, as the lane plan fixed
it), ``data_root``, ``checkpoints`` (branch -> file), ``output_dir``, ``proposals`` (the benchmark pass: ``semantic``
or ``gt``) and ``result``: where the steps' results go, pickled as ``{step: result}`` (the benchmark's
:func:`sdn3d.cli.bench.evaluate_bench`, with its pictures). Any error ends the process with a traceback and a
non-zero status; the demo names the task and this log.
"""

from __future__ import annotations

import json
import os
import pickle
import sys
from pathlib import Path


def run_task(spec: dict) -> dict:
    """The spec's steps' results (module doc)."""
    import torch
    from omegaconf import OmegaConf

    from sdn3d.cli import demo
    from sdn3d.cli.bench import evaluate_bench
    from sdn3d.proposals import Proposals

    cfg = OmegaConf.create(spec["config"])
    torch.manual_seed(int(cfg.seed))
    torch.set_num_threads(int(cfg.threads))
    root, out, ckpts = Path(spec["data_root"]), Path(spec["output_dir"]), dict(spec["checkpoints"])
    result: dict = {}
    for step in spec["steps"]:
        if step == "recall":
            result["recall"] = demo.run_proposal_recall(cfg, root, ckpts)
        elif step == "bench":
            bench = demo.bench_config(cfg, root, ckpts, out / "bench", [Proposals(spec["proposals"])])
            result["bench"] = evaluate_bench(bench)
        elif step == "edits":
            result["edits"] = demo.run_edits(cfg, root, ckpts, out / "edits")
        else:
            raise ValueError(f"unknown demo task step {step!r}")
    return result


def main(argv: list[str]) -> int:
    spec = json.loads(Path(argv[0]).read_text(encoding="utf-8"))
    result = run_task(spec)
    target = Path(spec["result"])
    tmp = target.with_name(target.name + ".tmp")
    with open(tmp, "wb") as stream:
        pickle.dump(result, stream)
    os.replace(tmp, target)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
