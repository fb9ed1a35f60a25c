"""Digest of what the editing wing draws, for checking that a refactor changes no picture.

Runs a fixed matrix of ``sdn3d-edit`` calls (the real Virtual KITTI frame of ``tests/data`` through boxes, every op,
both appearances, every fill and compose mode; a synthetic frame through ground-truth masks and the semantic branch)
and one ``sdn3d-bench`` run (photo / full / edited, predicted and oracle rows) with tiny random-weight branches
(``tests/helpers/tiny_models.py``, seed 0) and a small synthetic tree (seed 0), then writes one SHA-256 per output:
pictures and arrays by their pixels, JSON with its timing and path fields left out (they differ between any two
runs). Two digests of two source trees are compared with ``--compare A.json B.json``.

    .venv/bin/python scripts/output_digest.py --work /tmp/digest_before --out before.json
    PYTHONPATH=<other tree>/src:<other tree> .venv/bin/python scripts/output_digest.py --work /tmp/d2 --out after.json
    .venv/bin/python scripts/output_digest.py --compare before.json after.json
"""

from __future__ import annotations

import argparse
import hashlib
import io
import json
import os
import re
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
# key fragments of JSON fields that differ between any two runs of the same code (times, paths, the command line)
VOLATILE = ("time", "seconds", "elapsed", "wall", "started", "finished", "duration", "command", "path", "dir",
            "checkpoint", "sha256", "mtime", "host", "python", "torch_version", "version", "date", "cpu", "threads",
            "root", "file", "source_tree", "argv", "url")

# (name, spec ops, extra overrides): every op, both appearances, every fill and compose mode
EDITS = [
    ("list", [], []),
    ("rotate45", [{"op": "rotate", "id": 12001, "ry_deg": 45}], []),
    ("rotate180", [{"op": "rotate", "id": 12002, "ry_deg": 180}], []),
    ("move_zoom", [{"op": "move", "id": 12001, "to": [560, 300]}, {"op": "zoom", "id": 12002, "zoom": 1.3}], []),
    ("delete_auto", [{"op": "delete", "id": 12002}], []),
    ("delete_telea", [{"op": "delete", "id": 12002}], ["photo.fill=telea"]),
    ("delete_patchmatch", [{"op": "delete", "id": 12001}], ["photo.fill=patchmatch"]),
    ("delete_generator_fill", [{"op": "delete", "id": 12002}], ["photo.fill=generator"]),
    ("recolor_blue", [{"op": "recolor", "id": 12001, "color": "blue"}], []),
    ("duplicate", [{"op": "duplicate", "id": 12001, "to": [300, 300]}], []),
    ("no_relight", [{"op": "rotate", "id": 12001, "ry_deg": 90}], ["photo.relight=false", "photo.contact_shadow=0"]),
    ("generator_edited", [{"op": "rotate", "id": 12001, "ry_deg": 30}, {"op": "delete", "id": 12002}],
     ["appearance=generator"]),
    ("generator_full", [{"op": "move", "id": 12002, "to": [760, 280]}], ["appearance=generator", "compose=full"]),
    ("generator_recolor", [{"op": "recolor", "id": 12001, "code": [0.1, -0.2, 0.3, 0.0, 0.5]}],
     ["appearance=generator"]),
]


# an absolute path inside a string (e.g. "vkitti1 at /tmp/work/synth"): the run's working directory
ABSOLUTE_PATH = re.compile(r"(?<![\w.])/[\w.+-]+(?:/[\w.+-]*)*")


def _volatile(key: str) -> bool:
    """Timing fields (``derender_ms``, ``latency_ms``, ...) and :data:`VOLATILE` ones."""
    k = key.lower()
    return k.endswith("_ms") or "latency" in k or any(part in k for part in VOLATILE)


VOLATILE_KEYS: frozenset[str] = frozenset()  # --drop: whole keys added on purpose


def _canonical_json(value, key: str = ""):
    if isinstance(value, dict):
        return {k: _canonical_json(v, k) for k, v in sorted(value.items())
                if not _volatile(k) and k not in VOLATILE_KEYS}
    if isinstance(value, list):
        return [_canonical_json(v, key) for v in value]
    if isinstance(value, str) and ("/" in value and (value.startswith("/") or "outputs" in value)):
        return "<path>"
    if isinstance(value, str) and "/" in value:
        return ABSOLUTE_PATH.sub("<path>", value)
    return value


def digest_file(path: Path) -> str:
    """SHA-256 of a file's content as a picture / array / canonical JSON (volatile fields left out)."""
    suffix = path.suffix.lower()
    if suffix == ".json":
        data = _canonical_json(json.loads(path.read_text()))
        return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()
    if suffix == ".png":
        from PIL import Image

        with Image.open(path) as im:
            arr = np.asarray(im)
        return hashlib.sha256(arr.tobytes() + str(arr.shape).encode()).hexdigest()
    if suffix == ".npz":
        h = hashlib.sha256()
        with np.load(path, allow_pickle=False) as z:
            for name in sorted(z.files):
                arr = z[name]
                h.update(name.encode() + str(arr.shape).encode() + str(arr.dtype).encode() + arr.tobytes())
        return h.hexdigest()
    if suffix in (".html", ".md", ".txt", ".log", ".glb", ".yaml"):
        return ""  # prose and timing reports: compared through the JSON and pictures they are made from
    data = path.read_bytes()
    if zipfile.is_zipfile(io.BytesIO(data)):
        return ""
    return hashlib.sha256(data).hexdigest()


def digest_tree(root: Path) -> dict[str, str]:
    out = {}
    for path in sorted(root.rglob("*")):
        if path.is_file():
            d = digest_file(path)
            if d:
                out[str(path.relative_to(root))] = d
    return out


def _run(cmd: list[str], log: Path) -> int:
    started = time.perf_counter()
    with log.open("w") as fh:
        rc = subprocess.call(cmd, stdout=fh, stderr=subprocess.STDOUT, cwd=REPO)
    print(f"[digest] rc={rc} {time.perf_counter() - started:5.1f}s {' '.join(cmd[2:5])} ... -> {log.name}",
          file=sys.stderr)
    return rc


def make(work: Path) -> dict:
    import yaml

    sys.path.insert(0, str(REPO))
    from sdn3d.data.synth import SynthConfig, generate_dataset
    from tests.helpers.tiny_models import write_checkpoints

    work.mkdir(parents=True, exist_ok=True)
    ckpts = write_checkpoints(work / "ckpt", seed=0)
    synth = work / "synth"
    if not (synth / "_SUCCESS").exists():
        generate_dataset(SynthConfig(output_dir=str(synth), seed=0, image_size=(312, 96), frames_per_sequence=8,
                                     cars_per_frame=(3, 5), edit_pairs=3, max_edit_operations=2))
    py = sys.executable
    common = [f"checkpoints.{k}={v}" for k, v in ckpts.items()]
    results: dict[str, dict] = {}
    for name, ops, extra in EDITS:
        spec = work / "specs" / f"{name}.yaml"
        spec.parent.mkdir(exist_ok=True)
        spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": ops}))
        out = work / "edit" / name
        rc = _run([py, "-m", "sdn3d.cli.edit", f"input.image={FRAME}", "proposals=boxes", f"edits={spec}",
                   f"output_dir={out}", "diagnostics=true", *common, *extra], work / f"{name}.log")
        results[f"edit/{name}"] = {"rc": rc, **(digest_tree(out) if out.exists() else {})}
    frame_specs = {"gt": [{"op": "move", "id": 13001, "to": [170, 52]}, {"op": "rotate", "id": 13003, "ry_deg": 60},
                          {"op": "delete", "id": 12006}],
                   "semantic": []}  # tiny random branches: list what they propose
    for proposals, ops in frame_specs.items():
        frame_spec = work / "specs" / f"frame_{proposals}.yaml"
        frame_spec.write_text(yaml.safe_dump(ops))
        out = work / "edit" / f"frame_{proposals}"
        rc = _run([py, "-m", "sdn3d.cli.edit", "data=synth", f"data.root={synth}", "input.frame=6",
                   f"proposals={proposals}", f"edits={frame_spec}", f"output_dir={out}", *common],
                  work / f"frame_{proposals}.log")
        results[f"edit/frame_{proposals}"] = {"rc": rc, **(digest_tree(out) if out.exists() else {})}
    out = work / "bench"
    rc = _run([py, "-m", "sdn3d.cli.bench", f"data.root={synth}", f"output_dir={out}", "examples=2",
               *[c for c in common]], work / "bench.log")
    results["bench"] = {"rc": rc, **(digest_tree(out) if out.exists() else {})}
    return results


def demo_stages(demo: Path, work: Path) -> dict:
    """The demo's benchmark and example edits run again (this tree's code) with ``demo``'s trained checkpoints and
    data, and the digests of both runs' ``bench/`` and ``edits/``: ``{'demo/bench': ..., 'given/bench': ...}``."""
    import torch

    from sdn3d.cli._config import compose_config
    from sdn3d.cli.demo import _checkpoint, run_bench, run_edits

    info = json.loads((demo / "summary.json").read_text())
    ckpts = {b: _checkpoint(s) for b, s in info["training"].items()}
    out = work / "demo"
    cfg = compose_config([f"output_dir={out}", f"data_dir={demo / 'data'}"], "demo")
    torch.manual_seed(int(cfg.seed))
    torch.set_num_threads(int(cfg.threads))
    run_bench(cfg, demo / "data", ckpts, out / "bench")
    run_edits(cfg, demo / "data", ckpts, out / "edits")
    return {f"{side}/{part}": digest_tree(root / part) for side, root in (("demo", out), ("given", demo))
            for part in ("bench", "edits")}


def compare(a: dict, b: dict) -> int:
    files = differ = 0
    for group in sorted(set(a) | set(b)):
        ga, gb = a.get(group, {}), b.get(group, {})
        for key in sorted(set(ga) | set(gb)):
            files += 1
            if ga.get(key) != gb.get(key):
                differ += 1
                print(f"DIFFERS {group}/{key}: {ga.get(key)} vs {gb.get(key)}")
    print(f"{files} outputs compared (exit codes included), {differ} differ")
    return 1 if differ else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--work", type=Path, help="working directory for the runs")
    parser.add_argument("--out", type=Path, help="digest JSON to write")
    parser.add_argument("--compare", nargs=2, type=Path, metavar=("A", "B"), help="compare two digests")
    parser.add_argument("--demo", type=Path, metavar="DEMO_DIR",
                        help="instead of the matrix: run the demo's benchmark and example edits again with "
                             "DEMO_DIR's trained weights and data (an sdn3d-demo output) into --work/demo, write both "
                             "digests to --out (keys 'demo/<part>', 'given/<part>') and compare them")
    parser.add_argument("--drop", action="append", default=[], metavar="KEY",
                        help="a JSON key to leave out of the canonical form as well (a field added on purpose)")
    parser.add_argument("--redigest", nargs=2, type=Path, metavar=("WORK", "DIGEST"),
                        help="digest WORK's existing outputs again (exit codes from DIGEST; after a change to the "
                             "canonical form) into --out, without running anything")
    args = parser.parse_args()
    global VOLATILE_KEYS
    VOLATILE_KEYS = frozenset(args.drop)
    if args.demo and args.work and args.out:
        results = demo_stages(args.demo, args.work)
        args.out.write_text(json.dumps(results, indent=1, sort_keys=True))
        return compare({k[6:]: v for k, v in results.items() if k.startswith("given/")},
                       {k[5:]: v for k, v in results.items() if k.startswith("demo/")})
    if args.compare:
        return compare(*(json.loads(p.read_text()) for p in args.compare))
    if args.redigest and args.out:
        work, old = args.redigest[0], json.loads(args.redigest[1].read_text())
        results = {group: {"rc": entry.get("rc"), **(digest_tree(work / group) if (work / group).exists() else {})}
                   for group, entry in old.items()}
        args.out.write_text(json.dumps(results, indent=1, sort_keys=True))
        return 0
    if not (args.work and args.out):
        parser.error("give --work and --out, or --compare A B")
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    results = make(args.work)
    args.out.write_text(json.dumps(results, indent=1, sort_keys=True))
    print(f"[digest] {sum(len(v) for v in results.values())} entries -> {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
