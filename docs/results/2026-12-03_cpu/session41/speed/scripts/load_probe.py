# ruff: noqa: INP001, E501
"""The model loading of one ``sdn3d-edit`` call with and without ``TorchFiles(mmap=True)``, and the de-render after it,
each in a fresh interpreter, the two ways alternated: wall and CPU time and minor page faults of (1) resolving the
run's checkpoints and loading the models, (2) the de-render. Run with the worktree's ``src`` on ``PYTHONPATH``.

    python load_probe.py --pairs 8 -- run=... input.image=... edits=... threads=2 output_dir=/tmp/x

``read``: ``resolve_checkpoints`` and ``load_models`` without ``files`` (what the code before session 41 did: each
export unpickled twice, its weights read whole); ``mmap``: with one ``TorchFiles(mmap=True)`` (what ``run_edit`` now
does).
"""

import argparse
import dataclasses
import json
import os
import resource
import statistics
import subprocess
import sys
import time

FIELDS = ("load_ms", "load_cpu_ms", "load_minflt", "derender_ms", "derender_cpu_ms", "derender_minflt")


def _child(mode: str, overrides: list[str]) -> None:
    import torch

    import sdn3d.cli.edit as edit
    from sdn3d.cli._config import compose_config
    from sdn3d.editing.session import EditSession
    from sdn3d.editing.settings import appearance_settings, compose_settings, session_settings
    from sdn3d.io import TorchFiles

    cfg = compose_config(overrides, "edit")
    torch.set_num_threads(int(cfg.threads))
    _, spec, _, (inp, record) = edit._read_inputs(cfg)

    def now() -> tuple[float, float, int]:
        return time.perf_counter(), time.process_time(), resource.getrusage(resource.RUSAGE_SELF).ru_minflt

    files = TorchFiles(mmap=True) if mode == "mmap" else None
    a = now()
    checkpoints = edit.resolve_checkpoints(cfg, record, files)
    models, code_bank = edit.load_models(cfg, checkpoints, files)
    b = now()
    compose = compose_settings(cfg)
    appearance, photo = appearance_settings(cfg)
    settings = session_settings(cfg, checkpoints, compose, appearance, photo)
    settings = dataclasses.replace(settings, box_fit=edit.box_fit_for_input(cfg, settings.box_fit))
    session = EditSession(models, code_bank, settings)
    c = now()
    session.derender(inp, spec)
    d = now()
    print(json.dumps({"load_ms": 1000 * (b[0] - a[0]), "load_cpu_ms": 1000 * (b[1] - a[1]), "load_minflt": b[2] - a[2],
                      "derender_ms": 1000 * (d[0] - c[0]), "derender_cpu_ms": 1000 * (d[1] - c[1]),
                      "derender_minflt": d[2] - c[2]}), flush=True)
    os._exit(0)


def main() -> None:
    if len(sys.argv) > 2 and sys.argv[1] == "--child":
        _child(sys.argv[2], sys.argv[3:])
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pairs", type=int, default=8)
    parser.add_argument("--out")
    parser.add_argument("overrides", nargs="+")
    args = parser.parse_args()
    env = dict(os.environ)
    env.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    runs: dict[str, list[dict]] = {"read": [], "mmap": []}
    started = time.strftime("%Y-%m-%d %H:%M %Z")
    load = [os.getloadavg()[0]]
    for i in range(args.pairs):
        for mode in ("read", "mmap") if i % 2 == 0 else ("mmap", "read"):
            result = subprocess.run([sys.executable, __file__, "--child", mode, *args.overrides], env=env,
                                    capture_output=True, text=True, check=True)
            runs[mode].append(json.loads(result.stdout.strip().splitlines()[-1]))
        load.append(os.getloadavg()[0])
    print("| figure, median [min-max] | read (before) | mmap, read once (now) | now/before, median of pairs |")
    print("|---|---|---|---|")
    for key in FIELDS:
        cells = []
        for mode in ("read", "mmap"):
            v = [r[key] for r in runs[mode]]
            cells.append(f"{statistics.median(v):.0f} [{min(v):.0f}-{max(v):.0f}]")
        ratio = statistics.median(b[key] / a[key] for a, b in zip(runs["read"], runs["mmap"], strict=True))
        print(f"| {key} | {cells[0]} | {cells[1]} | {ratio:.3f} |")
    print(f"load average (1 min): {min(load):.2f}-{max(load):.2f}")
    if args.out:
        with open(args.out, "w") as handle:
            json.dump({"started": started, "overrides": args.overrides,
                       "load_average_1min": load, "runs": runs}, handle, indent=1)


if __name__ == "__main__":
    main()
