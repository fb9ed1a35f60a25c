"""CPU time the cyclic garbage collector takes in one ``sdn3d-edit`` call, measured from inside by ``gc.callbacks``.

    cd WORKTREE && OMP_NUM_THREADS=1 PYTHONPATH=CODE/src SDN3D_CONFIG_DIR=CODE/conf \
        python gc_time.py LABEL IMAGE SPEC RUN THREADS >> OUT.jsonl

The call is ``main()`` as the program runs it (arguments from ``sys.argv``, the process ended by ``_end_process``,
which prints the JSON first). Per phase (the import of ``sdn3d.cli.edit``, then ``main``): collections per
generation and their thread CPU time (``time.thread_time`` from each collection's start to its stop; collections run
on the thread that allocates), the number of objects frozen after the import (``gc.get_freeze_count``), the import's
and main's CPU and wall time. Prints one JSON line.
"""

from __future__ import annotations

import gc
import json
import sys
import time

STATS = {"n": [0, 0, 0], "cpu_s": [0.0, 0.0, 0.0]}
_start = [0.0]


def _callback(phase: str, info: dict) -> None:
    if phase == "start":
        _start[0] = time.thread_time()
    else:
        STATS["n"][info["generation"]] += 1
        STATS["cpu_s"][info["generation"]] += time.thread_time() - _start[0]


def _snapshot() -> dict:
    return {"n": list(STATS["n"]), "cpu_s": [round(v, 4) for v in STATS["cpu_s"]],
            "total_cpu_s": round(sum(STATS["cpu_s"]), 4)}


def main() -> None:
    label, image, spec, run, threads = sys.argv[1:6]
    gc.callbacks.append(_callback)
    t0, c0 = time.perf_counter(), time.process_time()
    import sdn3d.cli.edit as edit

    imported = {"wall_s": round(time.perf_counter() - t0, 3), "cpu_s": round(time.process_time() - c0, 3),
                "gc": _snapshot(), "frozen_objects": gc.get_freeze_count()}
    STATS["n"], STATS["cpu_s"] = [0, 0, 0], [0.0, 0.0, 0.0]
    t0, c0 = time.perf_counter(), time.process_time()
    end = edit._end_process

    def report_then_end(code: int) -> None:  # the program's own end (os._exit): print first
        called = {"wall_s": round(time.perf_counter() - t0, 3), "cpu_s": round(time.process_time() - c0, 3),
                  "gc": _snapshot()}
        print(json.dumps({"label": label, "exit": code, "import": imported, "main": called}), flush=True)
        end(code)

    edit._end_process = report_then_end
    sys.argv = ["sdn3d-edit", f"input.image={image}", f"edits={spec}", f"run={run}", f"threads={threads}",
                f"output_dir=/tmp/s26data/cost40/gc_time_{label}", "overwrite=true"]
    edit.main()  # as the program: argv from sys.argv, the process ends in _end_process


if __name__ == "__main__":
    main()
