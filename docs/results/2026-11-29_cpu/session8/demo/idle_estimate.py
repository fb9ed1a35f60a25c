# ruff: noqa: E501
"""Estimate a demo run's wall time on an idle machine from its lanes' CPU seconds.

usage: python idle_estimate.py OUTPUT_DIR [DATA_S]

Each lane task is one process with one torch thread, so on an idle core its wall time is about its CPU time (user +
system, recorded per task by the lanes runner as `cpu_s`). The estimate replays the demo's fixed plan
(sdn3d.cli.demo.lane_plan: which lane runs which task, and what each task waits for) with those CPU seconds as
durations, after the synthetic-data stage (DATA_S: its idle wall time, default 30 s, session 7's idle run; it runs
with 2 generator workers, not in the lanes), and adds the time the demo process spent after the lanes (writing the
benchmark and the report: measured wall, small).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def replay(timeline: list[dict], needs: dict[str, tuple[str, ...]]) -> tuple[float, dict[str, tuple[float, float]]]:
    lanes: dict[int, list[dict]] = {}
    for row in sorted(timeline, key=lambda r: r["start_s"]):
        lanes.setdefault(row["lane"], []).append(row)
    end: dict[str, float] = {}
    spans: dict[str, tuple[float, float]] = {}
    heads = {lane: 0 for lane in lanes}
    free = {lane: 0.0 for lane in lanes}
    while any(heads[lane] < len(rows) for lane, rows in lanes.items()):
        progressed = False
        for lane, rows in lanes.items():
            if heads[lane] >= len(rows):
                continue
            row = rows[heads[lane]]
            if all(n in end for n in needs[row["task"]]):
                start = max([free[lane]] + [end[n] for n in needs[row["task"]]])
                end[row["task"]] = free[lane] = start + row["cpu_s"]
                spans[row["task"]] = (start, end[row["task"]])
                heads[lane] += 1
                progressed = True
        if not progressed:
            raise ValueError("the plan cannot be replayed")
    return max(end.values()), spans


def main(out: Path, data_s: float) -> None:
    from sdn3d.cli.demo import lane_plan
    from sdn3d.proposals import Proposals

    info = json.loads((out / "summary.json").read_text())
    timeline = info["lanes"]["timeline"]
    plan = lane_plan(list(info["training"]), False, [Proposals.SEMANTIC, Proposals.GT])
    needs = {name: n for lane in plan for name, n in lane}
    lanes_s, spans = replay(timeline, needs)
    last_end = max(r["end_s"] for r in timeline)
    after = info["wall_s"] - last_end  # writing the benchmark and the report, measured
    print("| lane | task | CPU s | idle start s | idle end s |")
    print("|---|---|---|---|---|")
    for row in sorted(timeline, key=lambda r: (r["lane"], r["start_s"])):
        s, e = spans[row["task"]]
        print(f"| {row['lane']} | {row['task']} | {row['cpu_s']:.1f} | {data_s + s:.0f} | {data_s + e:.0f} |")
    total = data_s + lanes_s + after
    print(f"\nidle estimate: data {data_s:.0f} s + lanes {lanes_s:.0f} s + after the lanes {after:.1f} s = {total:.0f} s ({total / 60:.1f} min)")


if __name__ == "__main__":
    main(Path(sys.argv[1]), float(sys.argv[2]) if len(sys.argv) > 2 else 30.0)
