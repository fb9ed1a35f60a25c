# ruff: noqa: INP001, E501
"""Whole ``sdn3d-edit`` calls of two source trees, alternated: per call the wall time, user and system CPU time and
minor page faults of the process (``resource.getrusage(RUSAGE_CHILDREN)``); prints a table of medians [min-max] and
the median of the per-pair ratios, and writes every figure as JSON.

    python pairs.py --trees base=/tmp/s41base new=/tmp/s41new --pairs 8 --out pairs.json -- run=... input.image=... edits=... threads=2

Each tree is ``DIR/src`` (``PYTHONPATH``) and ``DIR/conf`` (``SDN3D_CONFIG_DIR``); every call writes its own fresh
output directory (deleted after the call, untimed). One untimed warm-up call per tree first (page cache, ``.pyc``
files); the order within a pair flips every other pair.
"""

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FIGURES = ("wall_s", "user_s", "sys_s", "cpu_s", "minflt")


def _call(tree: Path, overrides: list[str], out: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree / "src"), SDN3D_CONFIG_DIR=str(tree / "conf"))
    env.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run([sys.executable, "-m", "sdn3d.cli.edit", *overrides, f"output_dir={out}"], env=env,
                            capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode != 0:
        raise SystemExit(f"{tree}: exit {result.returncode}\n{result.stderr[-2000:]}")
    shutil.rmtree(out)
    user, system = after.ru_utime - before.ru_utime, after.ru_stime - before.ru_stime
    return {"wall_s": wall, "user_s": user, "sys_s": system, "cpu_s": user + system,
            "minflt": after.ru_minflt - before.ru_minflt}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trees", nargs=2, required=True, metavar="NAME=DIR")
    parser.add_argument("--pairs", type=int, default=8)
    parser.add_argument("--out")
    parser.add_argument("overrides", nargs="+")
    args = parser.parse_args()
    trees = dict(item.split("=", 1) for item in args.trees)
    names = list(trees)
    folder = Path(tempfile.mkdtemp(prefix="s41pairs_"))
    for name in names:
        _call(Path(trees[name]), args.overrides, folder / f"warm_{name}")
    calls: dict[str, list[dict]] = {n: [] for n in names}
    started = time.strftime("%Y-%m-%d %H:%M %Z")
    load = [os.getloadavg()[0]]
    for i in range(args.pairs):
        for name in names if i % 2 == 0 else names[::-1]:
            calls[name].append(_call(Path(trees[name]), args.overrides, folder / f"out_{name}_{i}"))
        load.append(os.getloadavg()[0])
    shutil.rmtree(folder, ignore_errors=True)
    a, b = names
    print(f"| figure, median [min-max] | {a} | {b} | {b}/{a}, median of pairs |")
    print("|---|---|---|---|")
    table = {}
    for key in FIGURES:
        row = {}
        for name in names:
            values = [c[key] for c in calls[name]]
            row[name] = {"median": statistics.median(values), "min": min(values), "max": max(values)}
        ratio = statistics.median(y[key] / x[key] for x, y in zip(calls[a], calls[b], strict=True))
        table[key] = {**row, "paired_ratio": ratio}
        cells = [f"{row[n]['median']:.3f} [{row[n]['min']:.3f}-{row[n]['max']:.3f}]" if key != "minflt" else
                 f"{row[n]['median']:.0f} [{row[n]['min']:.0f}-{row[n]['max']:.0f}]" for n in names]
        print(f"| {key} | {cells[0]} | {cells[1]} | {ratio:.3f} |")
    print(f"load average (1 min) during the pairs: {min(load):.2f}-{max(load):.2f}; cpus {os.cpu_count()}")
    if args.out:
        Path(args.out).write_text(json.dumps({"trees": trees, "overrides": args.overrides, "pairs": args.pairs,
                                              "started": started, "load_average_1min": load,
                                              "table": table, "calls": calls}, indent=1) + "\n")


if __name__ == "__main__":
    main()
