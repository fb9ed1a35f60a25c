"""One semantic training step (experiment=demo_short: forward, losses, backward, AdamW step) on a batch of the demo's
data, timed at 1 and 2 torch threads alternately in one process, each step with the share of the machine's CPU time
that other processes took meanwhile (/proc/stat minus this process): the 2-thread gain where the second core was free,
which a loaded shared machine otherwise hides. Usage: python step_threads.py DATA OUT.json [PAIRS]"""
# ruff: noqa: T201
from __future__ import annotations

import json
import os
import sys
import time

import torch
from hydra.utils import instantiate

from sdn3d.cli._config import compose_config


def cpu_ticks() -> tuple[int, int]:
    """(busy, total) jiffies of the whole machine."""
    fields = [int(v) for v in open("/proc/stat").readline().split()[1:]]
    idle = fields[3] + fields[4]
    return sum(fields) - idle, sum(fields)


def main(data: str, out: str, pairs: int = 15) -> None:
    cfg = compose_config(["branch=semantic", "experiment=demo_short", f"data.root={data}", "seed=0"], "train")
    torch.manual_seed(0)
    dm = instantiate(cfg.datamodule)
    dm.setup("fit")
    batch = next(iter(dm.train_dataloader()))
    model = instantiate(cfg.model)
    opt = torch.optim.AdamW(model.parameters(), lr=1e-4)
    hz = os.sysconf("SC_CLK_TCK")

    def step() -> None:
        terms = model.losses(model(batch["image"]), batch["label"], batch["instance"])
        opt.zero_grad()
        terms["loss"].backward()
        opt.step()

    torch.set_num_threads(1)
    step()
    torch.set_num_threads(2)
    step()  # warm both thread pools
    rows = []
    for i in range(2 * pairs):
        threads = 1 + i % 2
        torch.set_num_threads(threads)
        b0, t0 = cpu_ticks()
        c0, w0 = time.process_time(), time.perf_counter()
        step()
        c1, w1 = time.process_time(), time.perf_counter()
        b1, t1 = cpu_ticks()
        wall, cpu = w1 - w0, c1 - c0
        others = max(0.0, (b1 - b0) / hz - cpu)  # CPU seconds other processes used meanwhile
        rows.append({"threads": threads, "wall_s": round(wall, 3), "cpu_s": round(cpu, 3),
                     "others_cores": round(others / wall, 2), "load1": os.getloadavg()[0]})
        print(rows[-1], flush=True)
    json.dump(rows, open(out, "w"), indent=1)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 15)
