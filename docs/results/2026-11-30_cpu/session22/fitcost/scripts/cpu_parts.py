"""CPU seconds of chosen functions during one ``sdn3d-edit`` call in this process (``benchmarks/edit_cost.py``'s
wrapping, with more functions: the parts this helper looked at beside the phases). Prints JSON.

    cd TREE && OMP_NUM_THREADS=1 PYTHONPATH=src python WORKTREE/docs/results/2026-11-30_cpu/session22/fitcost/\
scripts/cpu_parts.py WORKTREE/benchmarks -- <sdn3d-edit overrides>

``thread_cpu_s`` is the calling thread's CPU time inside the function (its callees included).
"""

from __future__ import annotations

import json
import sys
import time

PARTS = (("sdn3d.cli.edit", "run_edit", "run_edit"),
         ("sdn3d.cli.edit", "compose_config", "compose_config"),
         ("sdn3d.cli.edit", "_read_inputs", "_read_inputs"),
         ("sdn3d.cli.edit", "resolve_checkpoints", "resolve_checkpoints"),
         ("sdn3d.cli.edit", "load_models", "load_models"),
         ("sdn3d.cli.edit", "session_settings", "session_settings"),
         ("sdn3d.cli.edit", "trust_warnings", "trust_warnings"),
         ("sdn3d.editing.session", "EditSession.derender", "derender"),
         ("sdn3d.editing.session", "EditSession.edit", "edit"),
         ("sdn3d.cli.edit", "_write_outputs", "_write_outputs"),
         ("sdn3d.runs", "trained_data", "runs.trained_data"),
         ("sdn3d.meshes.bank", "MeshBank.simplified", "MeshBank.simplified"),
         ("sdn3d.meshes.bank", "default_bank", "default_bank"),
         ("sdn3d.geometric.fit", "fit_to_masks", "fit_to_masks"),
         ("sdn3d.geometric.fit", "_stage", "fit._stage"),
         ("sdn3d.geometric.fit", "_search", "fit._search"))


def main() -> None:
    split = sys.argv.index("--")
    sys.path.insert(0, sys.argv[1])
    overrides = sys.argv[split + 1:]
    import edit_cost

    import sdn3d.cli.edit as edit

    startup = time.process_time()
    times: dict = {}
    for part in PARTS:
        edit_cost._wrap(times, *part)
    code = edit.main(overrides)
    print(json.dumps({"exit": code, "startup_cpu_s": round(startup, 3), "process_cpu_s": round(time.process_time(), 3),
                      "main_thread_cpu_s": round(time.thread_time(), 3),
                      "parts": {k: round(v["thread_cpu_s"], 3) for k, v in times.items()}}, indent=1))


if __name__ == "__main__":
    main()
