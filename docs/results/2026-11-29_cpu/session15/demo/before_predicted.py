"""The demo benchmark's predicted row with another semantic checkpoint (main's: 1 torch thread for all 14 epochs)
and a finished demo run's geometric and textural ones, written like the demo writes it (bench/results.json):
the "before" of a paired comparison with that run's own predicted row. Usage:
python before_predicted.py DEMO_OUT DATA SEMANTIC_CKPT OUT"""
# ruff: noqa: T201
from __future__ import annotations

import sys
from pathlib import Path

import torch

from sdn3d.cli._config import compose_config
from sdn3d.cli.bench import run_bench
from sdn3d.cli.demo import bench_config
from sdn3d.proposals import Proposals


def main(demo_out: str, data: str, semantic: str, out: str) -> None:
    runs = Path(demo_out) / "runs"
    ckpts = {"semantic": semantic,
             "geometric": str(next((runs / "geometric" / "checkpoints").glob("best-*.ckpt"))),
             "textural": str(next((runs / "textural" / "checkpoints").glob("best-*.ckpt")))}
    cfg = compose_config([f"output_dir={out}", f"data_dir={data}", "threads=1"], "demo")
    torch.manual_seed(int(cfg.seed))
    torch.set_num_threads(1)
    run_bench(bench_config(cfg, Path(data), ckpts, Path(out) / "bench", [Proposals.SEMANTIC]))
    print(ckpts)


if __name__ == "__main__":
    main(*sys.argv[1:5])
