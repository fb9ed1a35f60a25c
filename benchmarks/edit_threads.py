"""``sdn3d-edit`` with ``threads=1`` vs ``threads=2`` (PyTorch's default on 2 cores, sdn3d-edit's before issue 42).

One edit of the real 1242x375 frame with 3 boxes, a rotate and a move (random-weight branches), the two settings
alternating, N repeats (``python benchmarks/edit_threads.py N``, default 3); one JSON line per run: the whole call's
wall seconds, the 1-minute load average, edit.json's timings in seconds. docs/EDITING.md, "Threads".
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
REAL = ROOT / "tests" / "data" / "0006_30-deg-right_00043.png"
SPEC = ("objects:\n  - {box: [466, 203, 666, 333], class: Car}\n  - {box: [704, 194, 917, 305], class: Car}\n"
        "  - {box: [938, 190, 1060, 262], class: Car, force: true}\n"
        "ops:\n  - {op: rotate, id: 12001, ry_deg: 45}\n  - {op: move, id: 12002, to: [820, 300]}\n")
RUN = "import sys; from sdn3d.cli.edit import main; sys.exit(main(sys.argv[1:]))"


def main(repeats: int = 3) -> list[dict]:
    sys.path.insert(0, str(ROOT / "tests"))
    from helpers.tiny_models import write_checkpoints

    tmp = Path(tempfile.mkdtemp(prefix="edit_threads"))
    ckpts = write_checkpoints(tmp / "ckpt")
    spec = tmp / "spec.yaml"
    spec.write_text(SPEC)
    env = {k: v for k, v in os.environ.items() if k not in ("OMP_NUM_THREADS", "MKL_NUM_THREADS")}
    env["PYTHONPATH"] = f"{ROOT / 'src'}:{ROOT}"
    rows = []
    for rep in range(repeats):
        for threads in ([2, 1] if rep % 2 == 0 else [1, 2]):
            out = tmp / f"out{rep}_{threads}"
            args = [f"input.image={REAL}", f"edits={spec}", "proposals=boxes",
                    f"checkpoints.geometric={ckpts['geometric']}", f"checkpoints.textural={ckpts['textural']}",
                    "geometric.crop_size=32", f"output_dir={out}", f"threads={threads}"]
            start = time.perf_counter()
            done = subprocess.run([sys.executable, "-c", RUN, *args], env=env, capture_output=True, text=True)
            wall = time.perf_counter() - start
            timings = json.loads((out / "edit.json").read_text()).get("timings_ms", {}) if not done.returncode else {}
            rows.append({"rep": rep, "threads": threads, "rc": done.returncode, "wall_s": round(wall, 1),
                         "load1": round(os.getloadavg()[0], 2), **{k: round(v / 1000, 2) for k, v in timings.items()}})
            print(json.dumps(rows[-1]), flush=True)
            if done.returncode:
                print(done.stderr[-2000:], flush=True)
    return rows


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
