"""How much proposal recall a semantic-branch recipe buys per training step and per second (issue 28).

    python benchmarks/recall_budget.py --data-root DATA --out OUT/NAME --steps 400 --every 50 \\
        [--threads 2] [--part val] [--device cpu|cuda] -- [sdn3d-train overrides ...]

Trains the semantic branch exactly as the demo does (``sdn3d-train branch=semantic experiment=demo_short`` in a
child process, plus the overrides after ``--``) for ``--steps`` optimiser steps with no validation and no test,
keeping a checkpoint every ``--every`` steps. Then every kept checkpoint's instance proposals are scored on
``--part`` (default ``val``: a recipe is chosen there, never on the test part; ``--eval-root`` scores another
dataset's part instead, e.g. one generated with another seed) with the demo's measure
(:func:`sdn3d.evaluation.proposal_recall.predictor_recall`: Car and Van objects over 256 visible pixels at
624x192, found at IoU >= 0.5; precision = share of proposals covering some annotated object), the network
running at ``--work-size`` (default 312x96, the demo's).

Prints and writes ``OUT/NAME/recall.json``: per checkpoint its step, the training wall time to that step (from
the checkpoint files' write times, the child's start as zero: data indexing and model building included) and
recall / precision / proposals. Compare recipes by recall at equal wall time on one machine, measured side by
side; the step axis carries over between machines, the seconds do not.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))


def train(args: argparse.Namespace, overrides: list[str]) -> tuple[Path, float]:
    run_dir = Path(args.out).resolve()
    cmd = [sys.executable, "-m", "sdn3d.cli.train", "branch=semantic", "experiment=demo_short",
           f"data.root={Path(args.data_root).resolve()}", f"seed={args.seed}", f"threads={args.threads}",
           f"hydra.run.dir={run_dir}", f"summary_file={run_dir / 'summary.jsonl'}",
           f"trainer.max_steps={args.steps}", "trainer.max_epochs=100000", "trainer.limit_train_batches=null",
           "trainer.limit_val_batches=0", "trainer.num_sanity_val_steps=0", "test_after_fit=false",
           "~callbacks.model_checkpoint", "~callbacks.progress_bar",
           f"callbacks.step_checkpoint.every_n_train_steps={args.every}",
           "callbacks.step_checkpoint.save_top_k=-1", "+callbacks.step_checkpoint.filename='step{step:05d}'",
           "+callbacks.step_checkpoint.auto_insert_metric_name=false"]
    if args.device == "cuda":
        cmd.append("trainer=gpu")
    env = {"OMP_WAIT_POLICY": "PASSIVE", **os.environ, "OMP_NUM_THREADS": str(args.threads)}
    started = time.time()
    with open(run_dir.parent / f"{run_dir.name}.out", "w") as log:
        proc = subprocess.run([*cmd, *overrides], env=env, stdout=log, stderr=subprocess.STDOUT)
    if proc.returncode != 0:
        raise SystemExit(f"recall_budget: training failed (exit {proc.returncode}); see {log.name}")
    return run_dir, started


def score(args: argparse.Namespace, run_dir: Path, started: float) -> list[dict]:
    import torch

    from sdn3d.cli._config import synth_data_source
    from sdn3d.data.sources import load_split
    from sdn3d.evaluation.proposal_recall import PAPER_MIN_PIXELS, predictor_recall
    from sdn3d.semantic.predict import SemanticPredictor

    torch.set_num_threads(args.threads)
    source = synth_data_source(Path(args.eval_root or args.data_root))
    records = load_split(source, args.part)
    names = {c.id: c.name for c in source.class_list}
    rows = []
    for ckpt in sorted((run_dir / "checkpoints").glob("step*.ckpt")):
        step = int(re.search(r"step(\d+)", ckpt.name).group(1))
        predictor = SemanticPredictor.from_checkpoint(ckpt, map_location=args.device,
                                                      image_size=tuple(args.work_size))
        counts, _ = predictor_recall(records, predictor, PAPER_MIN_PIXELS)
        s = counts.summary(names)
        rows.append({"step": step, "train_s": round(ckpt.stat().st_mtime - started, 1), "recall": s["recall"],
                     "precision": s["precision"], "proposals": s["proposals"], "objects": s["objects"],
                     "recall_class_aware": s["recall_class_aware"]})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def main() -> int:
    argv = sys.argv[1:]
    overrides = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--data-root", required=True)
    p.add_argument("--out", required=True, help="run directory (created)")
    p.add_argument("--steps", type=int, default=400)
    p.add_argument("--every", type=int, default=50)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--part", default="val", choices=["train", "val", "test"])
    p.add_argument("--eval-root", default=None,
                   help="score on this dataset's --part instead (e.g. a synthetic set of another seed: a bigger "
                        "selection set than the training data's validation part, and still not its test part)")
    p.add_argument("--work-size", type=int, nargs=2, default=[312, 96])
    p.add_argument("--device", default="cpu", choices=["cpu", "cuda"])
    p.add_argument("--score-only", action="store_true", help="score the checkpoints of an existing --out")
    args = p.parse_args(argv)
    out = Path(args.out).resolve()
    if args.score_only:
        started = json.loads((out / "recall.json").read_text())["started"] if (out / "recall.json").exists() \
            else min(c.stat().st_mtime for c in (out / "checkpoints").glob("*.ckpt"))
        run_dir = out
    else:
        out.parent.mkdir(parents=True, exist_ok=True)
        run_dir, started = train(args, overrides)
    rows = score(args, run_dir, started)
    result = {"what": f"{args.part}-part proposal recall per training step (benchmarks/recall_budget.py)",
              "data_root": str(Path(args.data_root).resolve()),
              "eval_root": str(Path(args.eval_root or args.data_root).resolve()), "part": args.part,
              "steps": args.steps, "threads": args.threads, "device": args.device,
              "overrides": overrides, "started": started,
              "work_size": args.work_size, "rows": rows}
    tmp = out / "recall.json.tmp"
    tmp.write_text(json.dumps(result, indent=1))
    tmp.replace(out / "recall.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
