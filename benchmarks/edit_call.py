"""Wall time of one whole ``sdn3d-edit`` call, start-up and checkpoint loading included (issue 19); prints JSON.

    python benchmarks/edit_call.py --run DIR --image IMG [--edits SPEC] [--size 1242 375] [--repeats 5]
                                   [--modes checkpoints exports run] [--tree NAME=DIR ...]
                                   [--tree-mode checkpoints|exports|run] [--threads N]
                                   [--bytecode write|environment] [--stages] [--out FILE]

What one call is: the command a user types, ``python -m sdn3d.cli.edit run=... input.image=... edits=...
output_dir=...`` (the console script ``sdn3d-edit`` runs the same ``main``), started as a subprocess and
timed from its start to its exit: the interpreter's start-up, every import, the Hydra config, finding and
loading the three branches, de-rendering, editing, rendering and writing the output directory. Figures per
mode: the wall time (median, min, max and every value) and the child's CPU time (user + system,
``resource.getrusage(RUSAGE_CHILDREN)``, summed over its threads: on a shared, oversubscribed CPU the wall
time also counts waiting for a core, the CPU time does not).

Modes (``--modes``; the networks are the same in all of them, the weights identical):

- ``checkpoints``: the branches given as the Lightning checkpoints ``run=DIR`` selects
  (``checkpoints.<branch>=<file>.ckpt``, optimizer and loop state included);
- ``exports``: their inference exports (:mod:`sdn3d.inference_export`), written once, untimed, into a
  temporary folder (``checkpoints.<branch>=<file>.pt``);
- ``run``: ``run=DIR`` as a user types it (the run's ``checkpoints/inference.pt`` where one made from the
  selected checkpoint exists, else the checkpoint: ``sdn3d.runs``; the JSON says which files it loaded);
- ``NAME`` of each ``--tree NAME=DIR``: the mode ``--tree-mode`` names (default ``checkpoints``) run by another
  source tree (``PYTHONPATH=DIR/src``, ``SDN3D_CONFIG_DIR=DIR/conf``), e.g. the code before a change: ``git archive
  HEAD src conf | tar -x -C DIR``. Compare a tree with the same mode of this code (``--modes run --tree-mode run``):
  the modes load different files, and their times differ by more than most changes do.
  To compare two versions of the working tree side by side, copy each one's ``src/`` and ``conf/`` to a folder
  and give both as trees.

The input is ``--image`` resized to ``--size`` (default 1242x375, Virtual KITTI's frame: its camera is
known) and written to a temporary PNG. Without ``--edits``, one untimed ``list=true`` call finds the objects
and the spec moves the first object with geometry 40 px to the right, turns the second by 30 degrees and
deletes the third (as many as there are). Every mode gets one untimed warm-up call (page cache, ``.pyc``
files; see ``--bytecode``), then the timed calls are interleaved (mode A, B, C, A, B, C, ...) so that the load
of a shared machine falls on all modes alike; the JSON records the load average before and after and the CPU count.

``--bytecode`` (``write``, the default): the calls may write and read Python's ``.pyc`` files, as any
installed package's do (pip compiles them when it installs a wheel; Python writes them on the first import of
an editable install), so ``PYTHONDONTWRITEBYTECODE`` is dropped from the calls' environment and the warm-up call
writes them. ``environment``: the calls inherit the environment as it is; where ``PYTHONDONTWRITEBYTECODE`` is
set and the sources have no ``.pyc`` yet (a fresh clone), every call compiles each of sdn3d's ~100 modules from
source again (session 30's 4.39 s on its machine was measured so; docs/results/2026-12-01_cpu/session31/lead/).
The JSON records which.

``--stages`` adds, per mode, one call in a fresh interpreter that times its stages from inside: the import of
``sdn3d.cli.edit``, then each stage function of ``sdn3d.cli.edit`` (the config composition, checkpoint
lookup, model loading, de-rendering, edit, render, writing) by wrapping it, wall and CPU time
(``time.process_time``, all threads); and lists the heavy packages the call imported (``lightning``,
``torchmetrics``, ``tensorboard``, ``trimesh``, ``scipy``, ...).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
BRANCHES = ("semantic", "geometric", "textural")
MODES = ("checkpoints", "exports", "run")
#: Functions of sdn3d.cli.edit timed by --stages, where the module has them (the order of a call).
STAGE_FUNCTIONS = ("compose_config", "_read_inputs", "resolve_checkpoints", "load_models", "EditSession.derender",
                   "trust_warnings", "EditSession.edit", "_write_outputs", "_write_listing")
#: Packages whose presence after a call --stages reports.
HEAVY_PACKAGES = ("lightning", "lightning_fabric", "pytorch_lightning", "torchmetrics", "tensorboard", "matplotlib",
                  "trimesh", "networkx", "scipy", "kornia", "hydra", "omegaconf", "torchvision")
TARGET_S = 3.0


def _prepare_image(image: Path, size: tuple[int, int], folder: Path) -> Path:
    from PIL import Image

    with Image.open(image) as im:
        resized = im.convert("RGB").resize(size, Image.BICUBIC)
    out = folder / f"input_{size[0]}x{size[1]}.png"
    resized.save(out)
    return out


def _edit_command(python_args: list[str], overrides: list[str]) -> list[str]:
    return [sys.executable, *python_args, "-m", "sdn3d.cli.edit", *overrides]


def _environment(mode: str, trees: dict[str, Path], bytecode: str = "write") -> dict[str, str]:
    """The environment of a call: a tree's mode runs that tree's code and configs; ``bytecode`` as ``--bytecode``
    (module doc)."""
    env = dict(os.environ)
    if bytecode == "write":
        env.pop("PYTHONDONTWRITEBYTECODE", None)
    if mode in trees:
        env["PYTHONPATH"] = os.pathsep.join([str(trees[mode] / "src"), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
        env["SDN3D_CONFIG_DIR"] = str(trees[mode] / "conf")
    return env


def _timed_call(command: list[str], env: dict[str, str]) -> tuple[float, float, subprocess.CompletedProcess]:
    """``(wall s, child CPU s, result)`` of one subprocess run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(command, env=env, capture_output=True, text=True, cwd=REPO)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({result.returncode}):\n{result.stderr[-3000:]}")
    return wall, cpu, result


def _default_spec(overrides: list[str], env: dict[str, str], folder: Path) -> Path:
    """An edit spec from the objects one ``list=true`` call finds (module doc)."""
    listing = folder / "listing"
    _timed_call(_edit_command([], [*overrides, "list=true", f"output_dir={listing}"]), env)
    rows = json.loads((listing / "objects.json").read_text())["objects"]
    usable = [r for r in rows if r.get("template") is not None]
    if not usable:
        raise RuntimeError(f"the semantic branch finds no object with geometry in the image ({len(rows)} objects): "
                           "give --edits or another --image")
    width = json.loads((listing / "objects.json").read_text())["input_size"][0]
    ops = []
    first = usable[0]
    u, v = first["centre"]
    ops.append(f"- {{op: move, id: {first['id']}, to: [{min(u + 40, width - 1):.1f}, {v:.1f}]}}")
    if len(usable) > 1:
        ops.append(f"- {{op: rotate, id: {usable[1]['id']}, ry_deg: 30}}")
    if len(usable) > 2:
        ops.append(f"- {{op: delete, id: {usable[2]['id']}}}")
    spec = folder / "edits.yaml"
    spec.write_text("\n".join(ops) + "\n")
    return spec


def _mode_overrides(args: argparse.Namespace, folder: Path) -> dict[str, list[str]]:
    """Per mode, how the branches are given to sdn3d-edit."""
    from sdn3d.runs import export_checkpoint, find_run_checkpoints

    chosen, missing = find_run_checkpoints(args.run)
    if any(b not in chosen for b in BRANCHES):
        raise SystemExit(f"--run {args.run} lacks branches: {missing}")
    ckpts = {b: Path(chosen[b]["checkpoint"]) for b in BRANCHES}
    out: dict[str, list[str]] = {}
    exports: dict[str, Path] = {}
    for mode in [*args.modes, *args.trees]:
        how = args.tree_mode if mode in args.trees else mode  # a tree loads the branches as --tree-mode says
        if how == "checkpoints":
            out[mode] = [f"checkpoints.{b}={ckpts[b]}" for b in BRANCHES]
        elif how == "exports":
            exports = exports or {b: export_checkpoint(ckpts[b], folder / "exports" / f"{b}.pt") for b in BRANCHES}
            out[mode] = [f"checkpoints.{b}={exports[b]}" for b in BRANCHES]
        else:
            out[mode] = [f"run={Path(args.run).resolve()}"]
    return out


def _stages_child(argv: list[str]) -> None:
    """Inside a fresh interpreter: one call with its stages timed (module doc, ``--stages``); prints JSON."""
    start, start_cpu = time.perf_counter(), time.process_time()
    import sdn3d.cli.edit as edit

    imported, imported_cpu = time.perf_counter() - start, time.process_time() - start_cpu
    wall: dict[str, float] = {}
    cpu: dict[str, float] = {}

    def wrap(name: str) -> None:
        *path, attr = name.split(".")
        owner = edit
        for part in path:  # a method of a class sdn3d.cli.edit uses (EditSession: de-render; edit and draw)
            owner = getattr(owner, part)
        function = getattr(owner, attr)

        def timed(*args: Any, **kwargs: Any) -> Any:
            t0, c0 = time.perf_counter(), time.process_time()
            try:
                return function(*args, **kwargs)
            finally:
                wall[name] = wall.get(name, 0.0) + time.perf_counter() - t0
                cpu[name] = cpu.get(name, 0.0) + time.process_time() - c0

        setattr(owner, attr, timed)

    for name in STAGE_FUNCTIONS:
        wrap(name)  # a stale name fails here
    t0, c0 = time.perf_counter(), time.process_time()
    code = edit.main(argv)
    call, call_cpu = time.perf_counter() - t0, time.process_time() - c0
    loaded = sorted(p for p in HEAVY_PACKAGES if p in sys.modules)
    print(json.dumps({"exit": code,
                      "import_sdn3d_cli_edit_s": {"wall": round(imported, 3), "cpu": round(imported_cpu, 3)},
                      "main_s": {"wall": round(call, 3), "cpu": round(call_cpu, 3)},
                      "stages_s": {k: {"wall": round(v, 3), "cpu": round(cpu[k], 3)} for k, v in wall.items()},
                      "heavy_packages_loaded": loaded, "modules_loaded": len(sys.modules)}))


def _stages(mode: str, overrides: list[str], env: dict[str, str]) -> dict:
    command = [sys.executable, str(Path(__file__).resolve()), "--stages-child", *overrides]
    wall, cpu, result = _timed_call(command, env)
    report = json.loads(result.stdout.strip().splitlines()[-1])
    report["process_wall_s"], report["process_cpu_s"] = round(wall, 3), round(cpu, 3)
    return report


def _summary(values: list[float]) -> dict:
    return {"median": round(statistics.median(values), 3), "min": round(min(values), 3),
            "max": round(max(values), 3), "values": [round(v, 3) for v in values]}


def _loaded_files(output_dir: Path) -> dict:
    """Which files the call loaded per branch (its edit.json)."""
    record = json.loads((output_dir / "edit.json").read_text()).get("checkpoints") or {}
    return {b: (info or {}).get("path") for b, info in record.items()}


def run(args: argparse.Namespace) -> dict:
    folder = Path(tempfile.mkdtemp(prefix="sdn3d_edit_call_"))
    try:
        return _measure(args, folder)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _measure(args: argparse.Namespace, folder: Path) -> dict:
    image = _prepare_image(Path(args.image), tuple(args.size), folder)
    modes = _mode_overrides(args, folder)
    first = next(iter(modes))
    common = [f"input.image={image}"] + ([f"threads={args.threads}"] if args.threads else [])
    first_env = _environment(first, args.trees, args.bytecode)
    spec = Path(args.edits).resolve() if args.edits else _default_spec(common + modes[first], first_env, folder)
    calls = {m: [*common, *modes[m], f"edits={spec}", f"output_dir={folder / ('out_' + m)}"] for m in modes}
    load_before = os.getloadavg()
    files = {}
    for mode, overrides in calls.items():  # warm-up: page cache, .pyc files
        _timed_call(_edit_command([], overrides), _environment(mode, args.trees, args.bytecode))
        files[mode] = _loaded_files(folder / f"out_{mode}")
    wall: dict[str, list[float]] = {m: [] for m in calls}
    cpu: dict[str, list[float]] = {m: [] for m in calls}
    for _ in range(args.repeats):
        for mode, overrides in calls.items():
            w, c, _ = _timed_call(_edit_command([], overrides), _environment(mode, args.trees, args.bytecode))
            wall[mode].append(w)
            cpu[mode].append(c)
    report: dict[str, Any] = {
        "what": "one whole sdn3d-edit call as a subprocess (python -m sdn3d.cli.edit), start to exit",
        "target_s": TARGET_S, "image": str(args.image), "size": list(args.size), "edits": spec.read_text(),
        "repeats": args.repeats, "cpu_count": os.cpu_count(), "threads": args.threads,
        "OMP_NUM_THREADS": os.environ.get("OMP_NUM_THREADS"), "load_average_before": load_before,
        "load_average_after": os.getloadavg(), "trees": {k: str(v) for k, v in args.trees.items()},
        "tree_mode": args.tree_mode,
        "PYTHONPATH": os.environ.get("PYTHONPATH"),
        "bytecode": args.bytecode, "PYTHONDONTWRITEBYTECODE": first_env.get("PYTHONDONTWRITEBYTECODE"),
        "modes": {m: {"wall_s": _summary(wall[m]), "cpu_s": _summary(cpu[m]), "loaded": files[m],
                      "command": " ".join(["python -m sdn3d.cli.edit", *calls[m]])} for m in calls},
    }
    if args.stages:
        report["stages"] = {m: _stages(m, calls[m], _environment(m, args.trees, args.bytecode)) for m in calls}
    return report


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", required=True, help="a training output directory with the three branches")
    parser.add_argument("--image", required=True, help="the input picture (resized to --size)")
    parser.add_argument("--edits", help="an edit spec; default: made from the objects found (module doc)")
    parser.add_argument("--size", type=int, nargs=2, default=[1242, 375], metavar=("W", "H"))
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--modes", nargs="+", choices=MODES, default=["checkpoints", "exports", "run"])
    parser.add_argument("--tree", action="append", default=[], metavar="NAME=DIR",
                        help="also time --tree-mode with the source tree DIR (src/, conf/), as mode NAME")
    parser.add_argument("--tree-mode", choices=MODES, default="checkpoints",
                        help="how the trees load the branches (compare a tree with the same mode of this code)")
    parser.add_argument("--threads", type=int, help="sdn3d-edit threads= (default: PyTorch's)")
    parser.add_argument("--bytecode", choices=("write", "environment"), default="write",
                        help="write: the calls keep .pyc files as an installed package does (the warm-up writes "
                             "them); environment: as the environment says (module doc)")
    parser.add_argument("--stages", action="store_true", help="also time each stage once per mode, from inside")
    parser.add_argument("--out", help="also write the JSON here")
    return parser


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--stages-child":
        _stages_child(sys.argv[2:])
        return
    args = _parser().parse_args()
    args.trees = {}
    for item in args.tree:
        name, _, folder = item.partition("=")
        if not name or not folder or name in MODES or not (Path(folder) / "src" / "sdn3d").is_dir():
            raise SystemExit(f"--tree {item!r}: give NAME=DIR, NAME not one of {MODES}, DIR holding src/sdn3d")
        args.trees[name] = Path(folder).resolve()
    if args.repeats < 1:
        raise SystemExit("--repeats must be at least 1")
    report = run(args)
    text = json.dumps(report, indent=2)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")


if __name__ == "__main__":
    main()
