"""Where one whole ``sdn3d-edit`` call spends its time, phase by phase (issue 40: 10 boxes at 624x192 within 3 s).

    python benchmarks/edit_cost.py [--out FILE.json] -- <sdn3d-edit overrides: run=... input.image=... edits=...>

Runs the call in this process (as ``python -m sdn3d.cli.edit`` would, same arguments) and prints JSON: the CPU
seconds (``time.process_time``: all threads of the process) and wall seconds of each phase, measured by wrapping
these functions (a function's callees included, so the fit's rows overlap): the branches' loading
(``cli.edit.load_models``), the semantic branch, the first GrabCut of the boxes (``box_masks.grabcut_masks``), the
geometric branch, the fit (``geometric.fit.fit_to_masks``; its coarse search ``_search`` and every Adam stage
``_stage``), the second GrabCut seeded by the fitted shapes (``box_masks.refine_with_silhouettes``), the textural
encoder, the edit and its render (``EditSession.edit``) and writing the outputs. ``startup`` is the CPU time from the
interpreter's start until the CLI module is imported (torch, kornia, OpenCV, sdn3d). No profiler runs: the numbers
are the call's own. On a shared machine compare CPU seconds; wall seconds also count waiting for a core.

``cpu_s`` is the whole process's CPU time while the phase ran: where phases run on two threads at once (the fit's
groups; GrabCut beside the semantic branch) each counts the other's too. ``thread_cpu_s`` is the CPU time of the thread
that ran it (the threads torch or the soft-raster kernel start themselves not counted), and ``main_thread_cpu_s``
the main thread's for the whole process: on idle cores the wall time is about that plus its waits at the joins.
"""

from __future__ import annotations

import time

_T0 = time.perf_counter()

import argparse  # noqa: E402
import functools  # noqa: E402
import importlib  # noqa: E402
import json  # noqa: E402
import os  # noqa: E402
import sys  # noqa: E402
import threading  # noqa: E402
from pathlib import Path  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

#: (module, attribute, label) of each phase.
PHASES = (("sdn3d.cli.edit", "run_edit", "run_edit (everything after the imports)"),
          ("sdn3d.cli.edit", "load_models", "load the three branches"),
          ("sdn3d.derender", "_semantics_and_instances", "semantic branch"),
          ("sdn3d.box_masks", "grabcut_masks", "GrabCut masks (first pass)"),
          ("sdn3d.derender", "_geometry", "geometric branch"),
          ("sdn3d.geometric.fit", "fit_to_masks", "fit: all"),
          ("sdn3d.geometric.fit", "_search", "fit: coarse search"),
          ("sdn3d.geometric.fit", "_stage", "fit: Adam stages (the search's two and the fine one)"),
          ("sdn3d.box_masks", "refine_with_silhouettes", "GrabCut seeded by the fitted shapes (second pass)"),
          ("sdn3d.derender", "encode_scene", "textural encoder"),
          ("sdn3d.editing.session", "EditSession.edit", "edit and render"),
          ("sdn3d.cli.edit", "_write_outputs", "write the outputs"))


_LOCK = threading.Lock()  # phases may run on two threads at once (the fit's groups)


def _wrap(times: dict, module: str, attribute: str, label: str) -> None:
    owner = importlib.import_module(module)
    *path, name = attribute.split(".")
    for part in path:
        owner = getattr(owner, part)
    inner = getattr(owner, name)

    @functools.wraps(inner)
    def timed(*args, **kwargs):
        cpu, wall, own = time.process_time(), time.perf_counter(), time.thread_time()
        try:
            return inner(*args, **kwargs)
        finally:
            with _LOCK:
                entry = times.setdefault(label, {"cpu_s": 0.0, "thread_cpu_s": 0.0, "wall_s": 0.0, "calls": 0})
                entry["cpu_s"] += time.process_time() - cpu
                entry["thread_cpu_s"] += time.thread_time() - own
                entry["wall_s"] += time.perf_counter() - wall
                entry["calls"] += 1

    setattr(owner, name, timed)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("overrides", nargs="*", help="sdn3d-edit's arguments (after --)")
    args = parser.parse_args()
    import sdn3d.cli.edit as edit

    startup = time.process_time()
    times: dict = {}
    for phase in PHASES:
        _wrap(times, *phase)
    code = edit.main(args.overrides)
    result = {"what": "one sdn3d-edit call in this process, CPU (all threads) and wall seconds per phase",
              "arguments": args.overrides, "exit": code, "threads_env": os.environ.get("OMP_NUM_THREADS"),
              "omp_wait_policy": os.environ.get("OMP_WAIT_POLICY"), "load_average": os.getloadavg(),
              "startup_cpu_s": round(startup, 3), "process_cpu_s": round(time.process_time(), 3),
              "main_thread_cpu_s": round(time.thread_time(), 3),
              "process_wall_s": round(time.perf_counter() - _T0, 3),
              "phases": {k: {m: round(v, 3) if isinstance(v, float) else v for m, v in e.items()}
                         for k, e in times.items()}}
    text = json.dumps(result, indent=1)
    print(text)
    if args.out:
        args.out.write_text(text + "\n")


if __name__ == "__main__":
    main()
