"""Two code trees' ``sdn3d-edit`` calls side by side, taking turns (A B B A A B ...), each a fresh process timed from
its start to its exit: wall seconds and the child's CPU seconds (user + system, all threads). Prints and writes JSON.

    python ab_call.py --trees main=DIR br=DIR --out FILE.json --repeats 10 -- <sdn3d-edit overrides without
    output_dir>

Each tree is a ``git archive`` of ``src conf`` (its ``.pyc`` compiled beforehand, so that neither pays compiling);
each call runs with ``PYTHONPATH=DIR/src`` and ``SDN3D_CONFIG_DIR=DIR/conf`` into its own output directory
(``--outputs``/<name>). One untimed warm-up call per tree first. The order alternates per round (ABBA), so that a
trend in the shared machine's load falls on both alike; the paired figure is each round's ratio.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path


def _call(tree: Path, overrides: list[str], out: Path, threads_env: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree / "src"), SDN3D_CONFIG_DIR=str(tree / "conf"),
               OMP_NUM_THREADS=threads_env)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "sdn3d.cli.edit", *overrides, f"output_dir={out}", "overwrite=true"],
                          env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if done.returncode != 0:
        raise SystemExit(f"{tree}: exit {done.returncode}\n{done.stderr[-2000:]}")
    return {"wall_s": round(wall, 3), "cpu_s": round(cpu, 3), "load": round(os.getloadavg()[0], 2)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--trees", nargs=2, required=True, help="NAME=DIR NAME=DIR")
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--outputs", type=Path, default=Path("/tmp/s23data/callcost/ab_out"))
    parser.add_argument("--repeats", type=int, default=10)
    parser.add_argument("--omp", default="1", help="OMP_NUM_THREADS of the calls")
    parser.add_argument("overrides", nargs="*")
    args = parser.parse_args()
    trees = [(name, Path(path)) for name, path in (t.split("=", 1) for t in args.trees)]
    runs: dict[str, list[dict]] = {name: [] for name, _ in trees}
    for name, tree in trees:  # warm-up: page cache, the native kernel's library
        _call(tree, args.overrides, args.outputs / name, args.omp)
    for r in range(args.repeats):
        order = trees if r % 2 == 0 else trees[::-1]
        for name, tree in order:
            runs[name].append(_call(tree, args.overrides, args.outputs / name, args.omp))
        print(r, {name: runs[name][-1] for name, _ in trees}, flush=True)
    result = {"what": "sdn3d-edit calls, two trees taking turns (ABBA)", "trees": {n: str(t) for n, t in trees},
              "overrides": args.overrides, "omp_num_threads": args.omp, "cpu_count": os.cpu_count(), "runs": runs}
    args.out.write_text(json.dumps(result, indent=1) + "\n")


if __name__ == "__main__":
    main()
