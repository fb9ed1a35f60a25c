"""CPU seconds of ``compose_config(overrides, "edit")`` alone (what the register cut changes), two code trees taking
turns (ABBA), each round a fresh process: the imports first (untimed), then the one call the edit makes, timed with
``time.process_time``. Branch minus main per round with a 10,000-resample paired bootstrap 95 % interval.

    python compose_ab.py --trees main=DIR br=DIR --rounds 20 --out FILE.json
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

CHILD = """
import time
from sdn3d.cli._config import compose_config
import hydra, omegaconf  # noqa: F401  (imported by the edit before it composes)
start = time.process_time()
compose_config(["run=/tmp/s21data/demo/out/runs", "input.image=x.png"], "edit")
print(time.process_time() - start)
"""


def _once(tree: Path) -> float:
    env = dict(os.environ, PYTHONPATH=str(tree / "src"), SDN3D_CONFIG_DIR=str(tree / "conf"), OMP_NUM_THREADS="1")
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    done = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True, text=True, check=True)
    return float(done.stdout.split()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--trees", nargs=2, required=True, help="NAME=DIR NAME=DIR (main first)")
    parser.add_argument("--rounds", type=int, default=20)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    trees = [(name, Path(path)) for name, path in (t.split("=", 1) for t in args.trees)]
    runs: dict[str, list[float]] = {name: [] for name, _ in trees}
    for r in range(args.rounds):
        for name, tree in trees if r % 2 == 0 else trees[::-1]:
            runs[name].append(_once(tree))
    (a, _), (b, _) = trees
    d = np.array(runs[b]) - np.array(runs[a])
    rng = np.random.default_rng(0)
    means = d[rng.integers(0, len(d), size=(10_000, len(d)))].mean(1)
    lo, hi = np.percentile(means, [2.5, 97.5])
    summary = (f"compose_config CPU s: {a} median {np.median(runs[a]):.4f}, {b} median {np.median(runs[b]):.4f}; "
               f"{b} - {a} {d.mean():+.4f} [{lo:+.4f}, {hi:+.4f}], {b} lower/higher {(d < 0).sum()}/{(d > 0).sum()}")
    print(summary)
    args.out.write_text(json.dumps({"trees": {n: str(t) for n, t in trees}, "runs": runs, "summary": summary},
                                   indent=1) + "\n")


if __name__ == "__main__":
    main()
