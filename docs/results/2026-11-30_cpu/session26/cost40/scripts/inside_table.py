"""Tables of inside.sh's measurements: ``inside_table.py INSIDE_DIR``.

The collector's CPU per call (gc.jsonl: import and main, per tree, median of the rounds) and the stages of one call
(deep_stages.py's JSON: wall and thread CPU, median of the rounds per tree). Times in seconds.
"""

from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path


def main() -> None:
    folder = Path(sys.argv[1])
    rows = [json.loads(line) for line in (folder / "gc.jsonl").read_text().splitlines() if line.startswith("{")]
    print("| tree | calls | import CPU s | collections in import (gen 0/1/2) | collector CPU s in import | objects "
          "frozen | collections in main | collector CPU s in main | collector CPU s per call |")
    print("|---|---|---|---|---|---|---|---|---|")
    for tree in ("main", "cost40"):
        mine = [r for r in rows if r["label"] == tree]
        med = statistics.median
        print(f"| {tree} | {len(mine)} | {med(r['import']['cpu_s'] for r in mine):.3f} | "
              f"{'/'.join(str(n) for n in mine[0]['import']['gc']['n'])} | "
              f"{med(r['import']['gc']['total_cpu_s'] for r in mine):.3f} | {mine[0]['import']['frozen_objects']} | "
              f"{'/'.join(str(n) for n in mine[0]['main']['gc']['n'])} | "
              f"{med(r['main']['gc']['total_cpu_s'] for r in mine):.3f} | "
              f"{med(r['import']['gc']['total_cpu_s'] + r['main']['gc']['total_cpu_s'] for r in mine):.3f} |")
    stages: dict[str, dict[str, list]] = {}
    imports: dict[str, list] = {}
    for path in sorted(folder.glob("stages_*_*.json")):
        tree = path.stem.split("_")[1]
        report = json.loads(path.read_text())
        imports.setdefault(tree, []).append(report["import_s"])
        for name, (wall, cpu, _calls, _threads) in report["stages (wall s, thread cpu s, calls, threads)"].items():
            stages.setdefault(name, {}).setdefault(tree, []).append((wall, cpu))
        stages.setdefault("main (the whole call after the import)", {}).setdefault(tree, []).append(
            tuple(report["main_s"]))
    print()
    print("| stage | main wall s | main CPU s | cost40 wall s | cost40 CPU s |")
    print("|---|---|---|---|---|")

    def cell(values: list, i: int) -> str:
        return f"{statistics.median(v[i] for v in values):.3f}" if values else "-"

    print(f"| import sdn3d.cli.edit (process CPU) | {cell(imports.get('main', []), 0)} | "
          f"{cell(imports.get('main', []), 1)} | {cell(imports.get('cost40', []), 0)} | "
          f"{cell(imports.get('cost40', []), 1)} |")
    for name, per in stages.items():
        print(f"| {name} | {cell(per.get('main', []), 0)} | {cell(per.get('main', []), 1)} | "
              f"{cell(per.get('cost40', []), 0)} | {cell(per.get('cost40', []), 1)} |")


if __name__ == "__main__":
    main()
