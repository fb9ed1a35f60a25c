"""The box objects' de-render of the real frame in fresh `sdn3d-edit` processes, two source trees side by side.

    .venv/bin/python docs/results/2026-11-26_cpu/issue31_s3/cold_derender_ab.py RUN BEFORE_SRC AFTER_SRC [ROUNDS]

RUN: the demo's output (its geometric branch starts the fit). BEFORE_SRC / AFTER_SRC: two `src` directories (e.g. a
`git worktree` of the earlier commit and this checkout's). Each round runs one fresh process per tree, alternating
(A B A B ...), each listing the two cars of tests/data's real frame by their boxes (`proposals=boxes`, 2 threads), and
prints `edit.json`'s de-render time (GrabCut, the geometric branch, the fit, the second GrabCut) and whether the
process imported torch._dynamo. Writes nothing outside a temporary directory.
"""

import json
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[4]
IMAGE = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
CHILD = """
import json, sys, time
from pathlib import Path
from sdn3d.cli.edit import main
out = Path(sys.argv[1])
(out / "spec.yaml").write_text("objects:\\n  - {box: [466, 203, 666, 333], class: Car}\\n"
                               "  - {box: [704, 194, 917, 305], class: Car}\\n")
assert main([f"input.image={sys.argv[2]}", f"run={sys.argv[3]}", f"edits={out / 'spec.yaml'}", "proposals=boxes",
             f"output_dir={out / 'o'}", "threads=2"]) == 0
print(json.dumps({"derender_ms": json.loads((out / "o" / "edit.json").read_text())["timings_ms"]["derender_ms"],
                  "dynamo": "torch._dynamo" in sys.modules}))
"""


def main() -> None:
    run, trees, rounds = sys.argv[1], {"before": sys.argv[2], "after": sys.argv[3]}, int(sys.argv[4]) if len(
        sys.argv) > 4 else 4
    times = {name: [] for name in trees}
    for _ in range(rounds):
        for name, src in trees.items():
            with tempfile.TemporaryDirectory() as tmp:
                done = subprocess.run([sys.executable, "-c", CHILD, tmp, str(IMAGE), run], capture_output=True,
                                      text=True, env={"PYTHONPATH": src, "PATH": "/usr/bin:/bin"}, check=True)
            record = json.loads(done.stdout.strip().splitlines()[-1])
            times[name].append(record["derender_ms"])
            print(name, round(record["derender_ms"]), "ms; torch._dynamo imported:", record["dynamo"], flush=True)
    for name, values in times.items():
        values = sorted(values)
        print(f"{name}: de-render of 2 boxes, median {values[len(values) // 2]:.0f} ms, min {values[0]:.0f}, "
              f"max {values[-1]:.0f} ({len(values)} fresh processes)")


if __name__ == "__main__":
    main()
