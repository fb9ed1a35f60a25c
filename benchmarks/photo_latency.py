"""Latency of the photo appearance (sdn3d.editing.appearance.appearance_renderer('photo'): prepare, then draw) at
the input's resolution.

For every entry of a synthetic editing benchmark (default: a small dataset generated here at 1242x375, the Virtual
KITTI size), the source frame's ground-truth scene at the working size (624x192) is edited with the entry's
operations and drawn with the photo appearance at 1242x375. The scene is the oracle (ground-truth geometry), so the
figure is the drawing alone (a fresh source state per edit, unless --reuse-source): no network runs.
Times each fill method side by side in
one process, the same entries in the same order, after one warm-up call; prints, per fill method and per kind of
edit (sdn3d.evaluation.edit_benchmark.edit_kind), the median and 90th percentile of the wall time
(Drawn.times['photo_ms']) and the median CPU time of the process (prepare and draw; on a shared machine the wall
time grows with the load, the CPU time much less), and the process's peak resident memory.

``--reuse-source`` keeps one source state per source frame (its scene, input and
:class:`~sdn3d.editing.photo.transfer.PhotoSource`, with its fills) for all the edits of that frame, as an interactive
editor does: the first edit of a frame pays for it, the later ones reuse it (the default: a fresh state per edit).

``--against NAME=SRC`` times another checkout's code (its ``src`` directory) in the same run: each code runs in its
own worker process (this script with ``--serve``, the other code first on its path), and the workers take turns
edit by edit, so both see the same load.

    python benchmarks/photo_latency.py                       # generate the data in a temporary directory
    python benchmarks/photo_latency.py --data outputs/data/x  # a sdn3d-synth tree at 1242x375
    python benchmarks/photo_latency.py --fills auto --variant rays:fill=rays,delete_effects=true  # other settings
    python benchmarks/photo_latency.py --fills rays --against main=/path/to/main/src  # this code and main's
    python benchmarks/photo_latency.py --fills rays --reuse-source  # one source state per source frame
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import torch
import yaml


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--data", type=Path, default=None, help="a sdn3d-synth tree (default: generate one)")
    parser.add_argument("--fills", nargs="+", default=["telea", "patchmatch"])
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--limit", type=int, default=40)
    parser.add_argument("--variant", action="append", default=[],
                        help="NAME:key=value,... photo settings timed as one more column (repeatable)")
    parser.add_argument("--against", action="append", default=[],
                        help="NAME=SRC: another checkout's src directory, timed in the same run (repeatable)")
    parser.add_argument("--reuse-source", action="store_true",
                        help="one source state per source frame for all its edits (default: a fresh one per edit)")
    parser.add_argument("--json", type=Path, default=None,
                        help="also write every edit's kind, wall and CPU ms per fill (or code) to this JSON file")
    parser.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)  # a worker of --against
    args = parser.parse_args()
    torch.set_num_threads(args.threads)

    from sdn3d.data.edit_benchmark import load_edit_benchmark
    from sdn3d.data.records import load_rgb
    from sdn3d.data.scene_gt import scene_from_frame
    from sdn3d.data.synth import BENCHMARK_NAME, SynthConfig, generate_dataset
    from sdn3d.data.vkitti1 import read_frames
    from sdn3d.editing.appearance import appearance_renderer
    from sdn3d.editing.apply import apply_edits, ops_from_benchmark
    from sdn3d.editing.frame import PixelFrame
    from sdn3d.editing.photo.settings import PhotoSettings
    from sdn3d.evaluation.edit_benchmark import edit_kind

    tmp = None
    root = args.data
    if root is None:
        tmp = tempfile.TemporaryDirectory()
        root = Path(tmp.name) / "vkitti"
        generate_dataset(SynthConfig(output_dir=str(root), seed=3, image_size=(1242, 375), worlds=("0001", "0018"),
                                     variations=("clone",), frames_per_sequence=12, edit_pairs=6, occluder_pairs=2,
                                     workers=1))
    if args.against:
        _compare(args, root)
        if tmp is not None:
            tmp.cleanup()
        return
    records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(root)}
    entries = [e for e in load_edit_benchmark(root / BENCHMARK_NAME) if e.operations][: args.limit]
    work = (624, 192)
    cases = []
    sources: dict[tuple, tuple] = {}  # --reuse-source: one scene and input per source frame
    for entry in entries:
        key = (entry.world, entry.variation, entry.source_frame)
        record = records[key]
        if key not in sources or not args.reuse_source:
            sources[key] = (scene_from_frame(record, work),
                            torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1))
        scene, original = sources[key]
        edited = apply_edits(scene, ops_from_benchmark(entry, scene, (1242, 375), strict=False))
        cases.append((edit_kind(entry), scene, edited, original, key))
    size = tuple(int(x) for x in cases[0][3].shape[2:0:-1])
    frame = PixelFrame(size, work)
    settings = {fill: PhotoSettings(fill=fill) for fill in args.fills}
    for spec in args.variant:
        name, _, pairs = spec.partition(":")
        settings[name] = PhotoSettings.from_mapping({k: yaml.safe_load(v) for k, v in
                                                     (kv.split("=", 1) for kv in pairs.split(",") if kv)})
    times: dict[str, dict[str, list[float]]] = {f: {} for f in settings}
    cpu: dict[str, dict[str, list[float]]] = {f: {} for f in settings}
    renderers = {name: appearance_renderer("photo", photo=s) for name, s in settings.items()}
    warm = appearance_renderer("photo")  # warm-up (imports, PatchMatch's library)
    warm.draw(warm.prepare(cases[0][3], frame, cases[0][1]), cases[0][2])
    states: dict[tuple, object] = {}  # --reuse-source: (fill, source frame) -> its source state

    def one(i: int) -> dict[str, tuple[str, float, float]]:
        kind, scene, edited, original, key = cases[i]
        out = {}
        for fill, renderer in renderers.items():
            c0 = time.process_time()
            state = states.get((fill, key)) if args.reuse_source else None
            if state is None:
                state = renderer.prepare(original, frame, scene)
                if args.reuse_source:
                    states[(fill, key)] = state
            drawn = renderer.draw(state, edited)
            out[fill] = (kind, drawn.times["photo_ms"], 1000 * (time.process_time() - c0))
        return out

    if args.serve:  # a worker of --against: one edit per line read, its times as one JSON line
        print(json.dumps({"edits": len(cases)}), flush=True)
        for line in sys.stdin:
            print(json.dumps(one(int(line))), flush=True)
        return
    edits: dict[str, list[tuple[str, float, float]]] = {f: [] for f in settings}
    for i in range(len(cases)):
        for fill, (kind, wall, used) in one(i).items():
            times[fill].setdefault(kind, []).append(wall)
            cpu[fill].setdefault(kind, []).append(used)
            edits[fill].append((kind, wall, used))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    state = "one source state per source frame" if args.reuse_source else "a fresh source state per edit"
    print(f"photo appearance latency: {len(cases)} edits of {root} drawn at {size[0]}x{size[1]} from {work[0]}x"
          f"{work[1]} oracle scenes, {args.threads} threads, CPU, {state}; fills timed side by side, same entries and "
          "order")
    _table(times, cpu, args.json, edits)
    print(f"peak resident memory of this process: {peak:.0f} MiB")
    if tmp is not None:
        tmp.cleanup()


def _table(times: dict[str, dict[str, list[float]]], cpu: dict[str, dict[str, list[float]]],
           out: Path | None = None, edits: dict[str, list[tuple[str, float, float]]] | None = None) -> None:
    print("| fill | kind | edits | median ms | p90 ms | median CPU ms | p90 CPU ms |\n|---|---|---|---|---|---|---|")
    for fill, per_kind in times.items():
        every = [t for ts in per_kind.values() for t in ts]
        every_cpu = [t for ts in cpu[fill].values() for t in ts]
        for kind, ts in [("all", every), *sorted(per_kind.items())]:
            used = every_cpu if kind == "all" else cpu[fill][kind]
            p90 = float(np.percentile(ts, 90))
            print(f"| {fill} | {kind} | {len(ts)} | {statistics.median(ts):.0f} | {p90:.0f} | "
                  f"{statistics.median(used):.0f} | {float(np.percentile(used, 90)):.0f} |")
    if out is not None:  # every edit in order, for paired comparisons: {fill or code: [[kind, wall ms, CPU ms], ...]}
        from sdn3d.io import write_json_atomic  # this checkout's (the parent's), not an --against one's

        write_json_atomic(out, edits or {}, indent=1)


def _compare(args: argparse.Namespace, root: Path) -> None:
    """This code and each ``--against`` code in worker processes taking turns edit by edit (module doc)."""
    here = str(Path(__file__).resolve().parents[1] / "src")
    codes = [("this", here)] + [tuple(a.split("=", 1)) for a in args.against]
    forward = [*sum((["--variant", v] for v in args.variant), []), *(["--reuse-source"] if args.reuse_source else []),
               "--fills", *args.fills]
    workers = {}
    for name, src in codes:
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
        workers[name] = subprocess.Popen(
            [sys.executable, __file__, "--serve", "--data", str(root), "--threads", str(args.threads), "--limit",
             str(args.limit), *forward], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env)
    edits = {name: json.loads(w.stdout.readline())["edits"] for name, w in workers.items()}
    times: dict[str, dict[str, list[float]]] = {}
    cpu: dict[str, dict[str, list[float]]] = {}
    each: dict[str, list[tuple[str, float, float]]] = {}
    for i in range(min(edits.values())):
        for name, w in workers.items():  # the codes take turns: the same load on both
            w.stdin.write(f"{i}\n")
            w.stdin.flush()
            for fill, (kind, wall, used) in json.loads(w.stdout.readline()).items():
                times.setdefault(f"{name}:{fill}", {}).setdefault(kind, []).append(wall)
                cpu.setdefault(f"{name}:{fill}", {}).setdefault(kind, []).append(used)
                each.setdefault(f"{name}:{fill}", []).append((kind, wall, used))
    for w in workers.values():
        w.stdin.close()
        w.wait()
    state = "one source state per source frame" if args.reuse_source else "a fresh source state per edit"
    print(f"photo appearance latency: {min(edits.values())} edits of {root} at the input's size, {args.threads} "
          f"threads, CPU, {state}; codes {', '.join(f'{n}={s}' for n, s in codes)} in worker processes taking turns "
          "per edit")
    _table(times, cpu, args.json, each)


if __name__ == "__main__":
    main()
