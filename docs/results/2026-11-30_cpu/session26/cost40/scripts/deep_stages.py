"""Wall and CPU time of named functions inside one ``sdn3d-edit`` call, by perf_counter wrappers (no profiler).

    cd WORKTREE && OMP_NUM_THREADS=1 PYTHONPATH=CODE/src SDN3D_CONFIG_DIR=CODE/conf \
        python deep_stages.py IMAGE SPEC RUN THREADS [OUT_JSON]

Each entry ``module:qualname`` is wrapped in every module of ``sdn3d`` that holds it by name (``from x import f``
copies it), so a call is counted once whoever makes it. Times include callees; calls on worker threads are summed
under the same name (their thread names are recorded separately). Imports are timed from the first line.
"""

from __future__ import annotations

import json
import sys
import threading
import time
from collections import defaultdict

START = time.perf_counter(), time.process_time()

import sdn3d.cli.edit as edit  # noqa: E402

IMPORTED = time.perf_counter() - START[0], time.process_time() - START[1]

WRAP = [
    "sdn3d.cli.edit:compose_config", "sdn3d.cli.edit:load_models", "sdn3d.editing.session:EditSession.derender",
    "sdn3d.editing.session:EditSession.edit", "sdn3d.cli.edit:_write_outputs",
    "sdn3d.derender:box_grabcut", "sdn3d.derender:_semantics_and_instances", "sdn3d.derender:add_box_objects",
    "sdn3d.derender:_geometry", "sdn3d.derender:fit_proposals_and_boxes", "sdn3d.derender:fit_proposals",
    "sdn3d.derender:_choose_on_agreed_lamps", "sdn3d.derender:scene_maps",
    "sdn3d.geometric.fit:fit_many", "sdn3d.geometric.fit:_search", "sdn3d.geometric.fit:_stage",
    "sdn3d.geometric.fit:choose_again", "sdn3d.meshes.bank:MeshBank.simplified", "sdn3d.meshes.bank:default_bank",
    "sdn3d.box_objects:_refine_box_masks", "sdn3d.editing.photo.transfer:render_photo",
    "sdn3d.editing.photo.transfer:PhotoSource.__init__",
]


def main() -> None:
    image, spec, run, threads = sys.argv[1:5]
    wall: dict[str, float] = defaultdict(float)
    cpu: dict[str, float] = defaultdict(float)
    calls: dict[str, int] = defaultdict(int)
    where: dict[str, set] = defaultdict(set)

    def wrapper(name: str, function):
        def timed(*args, **kwargs):
            t0, c0 = time.perf_counter(), time.thread_time()
            try:
                return function(*args, **kwargs)
            finally:
                wall[name] += time.perf_counter() - t0
                cpu[name] += time.thread_time() - c0
                calls[name] += 1
                where[name].add(threading.current_thread().name)
        timed.__wrapped__ = function
        return timed

    for entry in WRAP:
        module_name, qual = entry.split(":")
        module = sys.modules.get(module_name) or __import__(module_name, fromlist=["x"])
        owner_path, attr = qual.rpartition(".")[0], qual.rpartition(".")[2]
        owner = module
        for part in filter(None, owner_path.split(".")):
            owner = getattr(owner, part)
        original = getattr(owner, attr)
        timed = wrapper(qual, original)
        if owner is module:  # every sdn3d module holding this function by name
            for other in list(sys.modules.values()):
                if getattr(other, "__name__", "").startswith("sdn3d") and getattr(other, attr, None) is original:
                    setattr(other, attr, timed)
        else:
            setattr(owner, attr, timed)
    t0, c0 = time.perf_counter(), time.process_time()
    code = edit.main([f"input.image={image}", f"edits={spec}", f"run={run}", f"threads={threads}",
                      "output_dir=/tmp/s26data/cost40/deep_out", "overwrite=true"])
    report = {"exit": code, "import_s": [round(v, 3) for v in IMPORTED],
              "main_s": [round(time.perf_counter() - t0, 3), round(time.process_time() - c0, 3)],
              "stages (wall s, thread cpu s, calls, threads)": {
                  k: [round(wall[k], 3), round(cpu[k], 3), calls[k], sorted(where[k])] for k in wall}}
    text = json.dumps(report, indent=1)
    print(text)
    if len(sys.argv) > 5:
        open(sys.argv[5], "w").write(text + "\n")


if __name__ == "__main__":
    main()
