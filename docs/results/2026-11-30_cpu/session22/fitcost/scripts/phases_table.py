"""Mean CPU seconds per phase of phases.sh's runs, two trees side by side (markdown).

    python phases_table.py OUTDIR NAME_A NAME_B
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def main() -> None:
    out, a, b = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
    runs = {n: [json.loads(p.read_text()) for p in sorted(out.glob(f"phases_{n}_r*.json"))] for n in (a, b)}
    print(f"| phase (threads=1) | {a} CPU s | {b} CPU s | {b} - {a} |")
    print("|---|---|---|---|")
    rows = [("start-up (imports)", lambda r: r["startup_cpu_s"]), ("whole process", lambda r: r["process_cpu_s"])]
    rows += [(k, lambda r, k=k: r["phases"][k]["thread_cpu_s"]) for k in runs[a][0]["phases"]]
    for label, get in rows:
        ma = sum(get(r) for r in runs[a]) / len(runs[a])
        mb = sum(get(r) for r in runs[b]) / len(runs[b])
        print(f"| {label} | {ma:.3f} | {mb:.3f} | {mb - ma:+.3f} |")
    print(f"\n{len(runs[a])} and {len(runs[b])} runs; load {[r['load_average'][0] for r in runs[a] + runs[b]]}")


if __name__ == "__main__":
    main()
