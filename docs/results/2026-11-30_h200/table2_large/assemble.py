"""Put the H200 call's seven Table 2 runs into one summary file for sdn3d-table2 (README.md says why).

    python docs/results/2026-11-30_h200/table2_large/assemble.py docs/results/2026-11-30_h200/table2_large
    sdn3d-table2 --summary docs/results/2026-11-30_h200/table2_large/runs.jsonl --experiment table2_large \
        --out docs/results/2026-11-30_h200/table2_large

The w/o L_reproj runs were trained and tested in the first call (runs_first_call.jsonl, written by sdn3d-train).
The full and MultiBin runs were trained in the first call (every epoch in epochs.txt), killed by the call's timeout
while testing, and tested in a second call with `sdn3d-train resume=<run dir>` (0 epochs left: the checkpoint
validation selected, tested): their <name>.summary.json. A resumed attempt's summary records neither the run's
experiment nor its first command line, nor training figures; this script adds (1) the experiment and the command
line benchmarks/table2_gpu.sh gave every run (the w/o L_reproj runs' own, with the ablation and seed of the run),
and (2) the last epoch's ``train/*`` figures from the run's per-epoch log line (epochs.txt, the same epoch means the
summary of a run that trains and tests in one attempt records). Nothing else is changed.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

RESUMED = ("full_s0", "full_s1", "full_s2", "full_multibin_s0")


def last_epoch_train_figures(epochs: str, run: str) -> dict[str, float]:
    """``train/*`` of the last ``epoch N/N done`` line under ``== .../<run>/`` in epochs.txt."""
    block = epochs.split(f"/runs/{run}/\n", 1)[1].split("\n== ", 1)[0]
    lines = [li for li in block.splitlines() if re.search(r"epoch (\d+)/\1 done", li)]
    if not lines:
        raise SystemExit(f"{run}: no last-epoch line in epochs.txt")
    figures = lines[-1].split("; ", 1)[1]
    return {k: float(v) for k, v in (item.rsplit(" ", 1) for item in figures.split(", ")) if k.startswith("train/")}


def main(folder: Path) -> None:
    records = [json.loads(line) for line in (folder / "runs_first_call.jsonl").read_text().splitlines() if line]
    template = records[0]["overrides"]
    epochs = (folder / "epochs.txt").read_text()
    for run in RESUMED:
        record = json.loads((folder / f"{run}.summary.json").read_text())
        ablation, seed = record["ablation"], record["seed"]
        record["experiment"] = "table2_large"
        record["overrides"] = [f"ablation={ablation}" if o.startswith("ablation=") else f"seed={seed}"
                               if o.startswith("seed=") else o for o in template]
        record["metrics"].update(last_epoch_train_figures(epochs, run))
        record["assembled"] = "experiment, overrides and train/* added by assemble.py (README.md)"
        records.append(record)
    (folder / "runs.jsonl").write_text("".join(json.dumps(r, sort_keys=True) + "\n" for r in records))
    print(f"wrote {folder / 'runs.jsonl'}: {len(records)} runs")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
