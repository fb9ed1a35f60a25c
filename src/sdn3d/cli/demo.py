"""``sdn3d-demo``: the README's main command, a short CPU run of the whole system.

1. ``data``: a synthetic street-scene dataset in the Virtual KITTI 1.3.1 format (+ its editing benchmark);
2. ``train``: the semantic, geometric and textural branches, each as an ``sdn3d-train experiment=demo_<budget>``
   run in its own process (checkpoints, TensorBoard and summaries under ``runs/``); the budgets are config
   files, ``conf/recipe/<branch>_demo_<budget>.yaml``;
3. ``bench``: the editing benchmark, 3D-SDN vs the 2D and 2D+ baselines (``sdn3d-bench``) on the test pairs;
4. ``edits``: one test frame de-rendered and edited: a car moved closer, rotated through several angles,
   recoloured, deleted;
5. ``report.md`` / ``summary.json``: what ran, the numbers, wall time and peak memory.

``budget=short`` (default) is the README's few-minute CPU run; ``budget=medium`` about half an hour on the
CPU; ``budget=long`` (``conf/budget/long.yaml``) is the longer documented run, meant for a GPU
(``device=cuda train.parallel=true workers=4``). The report names the budget and the device its numbers come from.
"""

from __future__ import annotations

import os
import platform
import re
import resource
import shutil
import subprocess
import sys
import time
from collections.abc import Sequence
from itertools import zip_longest
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import torch
from omegaconf import OmegaConf
from rich.console import Console

from sdn3d.editing.appearance import APPEARANCES, Appearance
from sdn3d.editing.compose import Compose, ComposeSettings
from sdn3d.errors import InputError
from sdn3d.proposals import Proposals
from sdn3d.training.start import ThreadsLater

console = Console(stderr=True)


class DemoStageError(RuntimeError):
    """A stage of the demo could not go on (a training run failed, wrote no checkpoint, ...); the message
    says which and where its log is. Exit status 1, no traceback."""


def _peak_rss_mib() -> dict[str, float]:
    """Peak resident memory of this process and of its largest child so far (Linux: KiB units)."""
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    child = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    return {"demo_process_mib": round(own, 1), "largest_child_mib": round(child, 1)}


def _load_average() -> list[float] | None:
    try:
        return [round(v, 2) for v in os.getloadavg()]
    except (OSError, AttributeError):  # not on every platform
        return None


def machine_record() -> dict:
    """What the report's times were measured on: the processor, its logical cores and the load average when the
    demo started (a loaded machine takes twice as long or more: the report says which it was)."""
    model = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"processor": model, "logical_cpus": os.cpu_count(), "load_average_start": _load_average()}


def stage_rows(info: dict) -> str:
    """The report's stage-time table: data, each branch's training, the benchmark, the edits and the whole run."""
    stages = info.get("stages_s") or {}
    rows = [("synthetic data", stages.get("data"))]
    if info.get("lanes"):  # the stages overlap: each lane's tasks with their start and end
        rows += [(f"lane {r['lane']}: {r['task']}, {threads_words(r['threads'])} "
                  f"(from {r['start_s']:.0f} s to {r['end_s']:.0f} s"
                  + (f"; CPU {r['cpu_s']:.0f} s" if r.get("cpu_s") is not None else "") + ")", r["wall_s"])
                 for r in sorted(info["lanes"]["timeline"], key=lambda r: (r["lane"], r["start_s"]))]
        rows += [("training, all branches (lanes overlapping)", stages.get("train")),
                 ("after the last training (the rest of the lanes, the benchmark written)",
                  stages.get("after_training")), ("whole demo", info.get("wall_s"))]
        return "\n".join(f"| {name} | {sec:.0f} |" if isinstance(sec, (int, float)) else f"| {name} | n/a |"
                         for name, sec in rows)
    rows += [(f"training: {b}", (s or {}).get("demo_wall_s")) for b, s in (info.get("training") or {}).items()]
    rows += [("training, all branches", stages.get("train")), ("editing benchmark (with proposal recall)",
                                                                 stages.get("bench")),
             ("example edits", stages.get("edits")), ("whole demo", info.get("wall_s"))]
    return "\n".join(f"| {name} | {sec:.0f} |" if isinstance(sec, (int, float)) else f"| {name} | n/a |"
                     for name, sec in rows)


def machine_sentence(info: dict) -> str:
    """One sentence naming the machine the times were measured on, and how loaded it was."""
    m = info.get("machine") or {}
    loads = [v for v in (m.get("load_average_start"), m.get("load_average_end")) if v]
    load = (f"; 1-minute load average {loads[0][0]:.1f} at the start" +
            (f" and {loads[-1][0]:.1f} at the end" if len(loads) > 1 else "") if loads else "")
    busy = ""
    if loads and m.get("logical_cpus") and max(v[0] for v in loads) > 1.5 * m["logical_cpus"]:
        busy = " (a busy machine: other work competed for the cores, so these times are longer than a quiet run's)"
    return (f"Measured on {m.get('processor', 'an unknown processor')}, {m.get('logical_cpus', '?')} logical cores, "
            f"{threads_phrase(info)}{load}{busy}.")


def threads_phrase(info: dict) -> str:
    """``2 torch threads``, or with lanes ``2 lanes (training: semantic 1 torch thread for its first 7 epochs, then
    2; every other stage 1 torch thread)``: each task's threads as the lane plan fixed them
    (:func:`threads_sentence`)."""
    lanes = info.get("lanes")
    if lanes:
        return f"{lanes['lanes']} lanes ({threads_sentence(lanes['threads'])})"
    return f"{info.get('threads')} torch threads"


def _stage(name: str) -> None:
    console.rule(f"[bold]sdn3d-demo: {name}")


#: The files the synthetic generator writes (relative POSIX paths): anything else in ``data_dir`` is the user's.
_GENERATED = re.compile(r"(_SUCCESS|class_statistics\.json|synth_manifest\.json|vkitti_edit_benchmark\.json"
                        r"|vkitti_1\.3\.1_(rgb|depthgt|scenegt)/\d{4}/[\w+-]+/\d{5}\.png"
                        r"|vkitti_1\.3\.1_(extrinsicsgt|motgt)/\d{4}_[\w+-]+\.txt"
                        r"|vkitti_1\.3\.1_scenegt/\d{4}_[\w+-]+_scenegt_rgb_encoding\.txt)")


def _not_generated(root: Path) -> list[str]:
    """Entries under ``root`` the synthetic generator does not write (links included: never followed)."""
    found = []
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root).as_posix()
        if path.is_symlink() or (path.is_file() and not _GENERATED.fullmatch(rel)) or not (
                path.is_file() or path.is_dir()):
            found.append(rel)
    return found


def make_data(cfg: Any) -> Path:
    """The synthetic dataset in ``data_dir``: reused when an earlier run generated it with the same settings (the
    generator is deterministic), else generated. A ``data_dir`` holding a file the generator did not write is
    refused, naming it (replacing the dataset would delete it).

    Raises:
        InputError: ``data_dir`` holds files of the user's.
    """
    import json

    from sdn3d.data.synth import SynthConfig, generate_dataset

    root = Path(str(cfg.data_dir))
    synth = OmegaConf.to_container(cfg.synth, resolve=True)
    config = SynthConfig(output_dir=str(root), seed=int(cfg.seed), overwrite=True, threads=1, **synth)
    if root.is_dir() and any(root.iterdir()):
        wanted = config.recorded()
        try:
            recorded = json.loads((root / "synth_manifest.json").read_text(encoding="utf-8")).get("config")
        except (OSError, ValueError, AttributeError):
            recorded = None
        if (root / "_SUCCESS").is_file() and recorded == json.loads(json.dumps(wanted)):
            console.print(f"sdn3d-demo: reusing the synthetic data in {root} (generated with the same settings)")
            return root
        foreign = _not_generated(root)
        if foreign:
            shown = ", ".join(repr(f) for f in foreign[:5]) + (f" and {len(foreign) - 5} more" if len(foreign) > 5
                                                               else "")
            raise InputError(f"data_dir {str(root)!r} holds {len(foreign)} entries the synthetic generator did not "
                             f"write ({shown}): regenerating the data would delete them; move them out or choose "
                             "another data_dir")
    generate_dataset(config)
    return root


def _train_command(branch: str, cfg: Any, data_root: Path, runs: Path, upstream: dict[str, str] | None = None,
                   to_file: bool = False, later: ThreadsLater | None = None) -> list[str]:
    """The ``sdn3d-train`` child: the branch's experiment (its budget) plus this machine's options; then the
    user's extra ``train.common`` / ``train.<branch>`` overrides (empty by default).

    ``upstream``: checkpoints of the branches trained before (3D-SDN's order): the textural run gets the semantic
    and geometric ones, which its recipe uses when it trains on predicted maps (``datamodule.maps=predicted``),
    with the predicted-map cache under ``runs/map_cache``. ``to_file``: its output goes to a file (the lanes), so
    without a progress bar, as with ``train.parallel``. ``later``: its ``threads_later`` (the lanes' plan)."""
    experiment = (cfg.train.get("experiment") or {}).get(branch, f"demo_{cfg.budget_name}")
    args = [sys.executable, "-m", "sdn3d.cli.train", f"branch={branch}", f"experiment={experiment}",
            f"data.root={data_root.resolve()}", f"seed={int(cfg.seed)}", f"threads={int(cfg.threads)}",
            f"datamodule.num_workers={int(cfg.workers)}", f"hydra.run.dir={runs / branch}",
            f"summary_file={runs / 'summary.jsonl'}"]
    upstream = upstream or {}
    if branch == "textural" and "semantic" in upstream and "geometric" in upstream:
        args += [f"datamodule.semantic_checkpoint={upstream['semantic']}",
                 f"datamodule.geometric_checkpoint={upstream['geometric']}",
                 f"datamodule.map_cache_dir={runs / 'map_cache'}"]
    if later is not None:
        args.append(f"threads_later={{after_epochs:{later.after_epochs},threads:{later.threads}}}")
    if cfg.device != "cpu":
        args.append("trainer=gpu")
    if cfg.train.get("parallel") or to_file:  # several progress bars on one terminal would garble each other
        args += ["trainer.enable_progress_bar=false", "~callbacks.progress_bar"]
    return args + [str(o) for o in cfg.train.common] + [str(o) for o in cfg.train.get(branch, [])]


def _train_env(cfg: Any) -> dict[str, str]:
    # PASSIVE: idle OpenMP threads sleep instead of spinning; on a busy 2-core machine spinning threads
    # made each training step about 1.7x slower (DRN-D-22, 312x96, batch 8: 36 s -> 20 s at load 7).
    return {"OMP_WAIT_POLICY": "PASSIVE", **os.environ, "OMP_NUM_THREADS": str(int(cfg.threads))}


def _finish(branch: str, run_dir: Path, returncode: int, started: float, new_run: Path | None = None) -> dict:
    """The new run's summary.json; ``new_run``: where :func:`_keep_or_restore` left it (``runs/<branch>.failed``
    when an earlier run was put back in ``run_dir``)."""
    import json

    new_run = new_run or run_dir
    if returncode != 0 or new_run != run_dir:
        kept = f"; the earlier run is kept in {run_dir}" if new_run != run_dir else ""
        raise DemoStageError(f"training the {branch} branch failed (exit {returncode}); see {new_run}/train.log{kept}")
    summary = json.loads((run_dir / "summary.json").read_text())
    summary["demo_wall_s"] = round(time.perf_counter() - started, 1)
    return summary


def _finished_ok(run_dir: Path) -> bool:
    import json

    try:
        return json.loads((run_dir / "summary.json").read_text(encoding="utf-8")).get("status") == "ok"
    except (OSError, ValueError, AttributeError):
        return False


def _previous(run_dir: Path) -> Path:
    """Where an earlier run of the branch waits while it is trained again: ``runs/.<branch>.previous``."""
    return run_dir.parent / f".{run_dir.name}.previous"


def _set_aside(run_dir: Path) -> None:
    """Before a branch is trained again: its earlier run is moved to :func:`_previous` (not deleted), after putting
    back one that an interrupted demo left there (:func:`_keep_or_restore`)."""
    _keep_or_restore(run_dir, interrupted=True)
    if run_dir.exists():
        os.rename(run_dir, _previous(run_dir))


def _keep_or_restore(run_dir: Path, interrupted: bool = False) -> Path:
    """After training ``run_dir`` again (or, ``interrupted``, before, for a demo that was killed meanwhile): a new
    run that finished ok replaces the earlier one (removed); otherwise the new run is kept as
    ``runs/<branch>.failed`` and the earlier one goes back to ``run_dir``: its weights are never lost. Returns where
    the new run is."""
    previous = _previous(run_dir)
    if not previous.exists():
        return run_dir
    if run_dir.exists() and _finished_ok(run_dir):
        shutil.rmtree(previous)
        return run_dir
    failed = run_dir.parent / f"{run_dir.name}.failed"
    if run_dir.exists():
        if failed.exists():
            shutil.rmtree(failed)
        os.rename(run_dir, failed)
    os.rename(previous, run_dir)
    console.print(f"sdn3d-demo: the earlier {run_dir.name} run is kept in {run_dir}"
                  + (" (the demo that trained it again was interrupted)" if interrupted else ""))
    return failed


def train_branch(branch: str, cfg: Any, data_root: Path, runs: Path, upstream: dict[str, str] | None = None) -> dict:
    """One ``sdn3d-train`` run in a child process (its own progress bar); returns its summary.json. An earlier run
    of the branch is replaced only once the new one finished ok (:func:`_keep_or_restore`)."""
    run_dir = runs / branch
    _set_aside(run_dir)
    started = time.perf_counter()
    proc = None
    try:
        proc = subprocess.run(_train_command(branch, cfg, data_root, runs, upstream), env=_train_env(cfg))
    finally:
        new_run = _keep_or_restore(run_dir)
    return _finish(branch, run_dir, proc.returncode, started, new_run)


def train_parallel(branches: Sequence[str], cfg: Any, data_root: Path, runs: Path,
                   upstream: dict[str, str] | None = None) -> dict[str, dict]:
    """All branches at once, one child process each (``train.parallel``: a GPU has room for the three);
    their output goes to ``runs/<branch>.out``. Returns the summaries; the first failure raises once all ended."""
    procs = {}
    runs.mkdir(parents=True, exist_ok=True)
    for branch in branches:
        _set_aside(runs / branch)
        log = open(runs / f"{branch}.out", "w")  # noqa: SIM115 - closed below, after the child ends
        procs[branch] = (subprocess.Popen(_train_command(branch, cfg, data_root, runs, upstream), env=_train_env(cfg),
                                          stdout=log, stderr=subprocess.STDOUT), log, time.perf_counter())
    codes = {}
    try:
        for branch, (proc, log, started) in procs.items():
            codes[branch] = proc.wait()
            log.close()
            console.print(f"sdn3d-demo: {branch} branch finished (exit {codes[branch]}, "
                          f"{time.perf_counter() - started:.0f} s; output in {runs / f'{branch}.out'})")
    finally:
        new_runs = {b: _keep_or_restore(runs / b) for b in branches}
    return {b: _finish(b, runs / b, codes[b], procs[b][2], new_runs[b]) for b in branches}


def _textural_needs_upstream(cfg: Any) -> bool:
    """Whether the textural run trains on the semantic and geometric branches' predicted maps
    (``datamodule.maps=predicted``: the medium and long budgets) and so must wait for them; the short budget's
    trains on the frames' ground-truth maps and can train beside them (``lanes``)."""
    from sdn3d.cli._config import compose_config

    experiment = (cfg.train.get("experiment") or {}).get("textural", f"demo_{cfg.budget_name}")
    overrides = ["branch=textural", f"experiment={experiment}", *(str(o) for o in cfg.train.common),
                 *(str(o) for o in cfg.train.get("textural", []))]
    return str(compose_config(overrides, "train").datamodule.maps) == "predicted"


def _train_name(branch: str) -> str:
    return f"training: {branch}"


#: The lanes' names of the benchmark's passes and of the example edits.
BENCH_TASKS = {Proposals.SEMANTIC: "benchmark: predicted row",
               Proposals.GT: "benchmark: oracle row"}
EDITS_TASK = "example edits (and proposal recall)"


class PlannedTask(NamedTuple):
    """One stage of :func:`lane_plan`: its name, the tasks it waits for (in any lane), its torch threads and, for a
    training, the more threads it takes from a given epoch on (``later``; None: ``threads`` throughout). Fixed by the
    plan before anything runs, never by timing or by what the other lane is doing."""

    name: str
    needs: tuple[str, ...]
    threads: int
    later: ThreadsLater | None = None


def lane_plan(branches: Sequence[str], textural_needs_upstream: bool, bench: Sequence[Proposals], threads: int,
              semantic_threads_after: int | None = None) -> list[list[PlannedTask]]:
    """The demo's two lanes: per lane, its tasks in the order it runs them (:mod:`sdn3d.cli._lanes`). Lane 1 trains
    the semantic branch (the longest), then runs the benchmark's predicted row; lane 2 trains the geometric and
    textural branches (which do not need the semantic one unless ``textural_needs_upstream``), runs the oracle row
    (it needs no semantic branch: usually while lane 1 still trains), then the example edits and, with a predicted
    row, the semantic branch's proposal recall (both need every branch: they run beside the predicted row, the longer
    task, which the recall would otherwise lengthen). Without a semantic branch lane 1 trains the geometric one.

    Threads: every task has its lane's share, ``threads // 2`` (at least 1), except the semantic training, the
    critical path: from its epoch ``semantic_threads_after`` on (0: from its start) it has all ``threads``, lane 2's
    core being free by then (on an idle machine lane 2 is done with its stages about half way through the semantic
    training, then only waits for it); None: its share throughout."""
    share = max(1, int(threads) // 2)
    semantic = PlannedTask(_train_name("semantic"), (), share)
    if semantic_threads_after is not None and int(threads) > share:
        semantic = semantic._replace(threads=int(threads)) if int(semantic_threads_after) == 0 else \
            semantic._replace(later=ThreadsLater(int(semantic_threads_after), int(threads)))
    train = {b: _train_name(b) for b in branches}
    needs = {b: () for b in branches}
    if "textural" in branches and textural_needs_upstream:
        needs["textural"] = tuple(train[b] for b in ("semantic", "geometric") if b in branches)
    planned = {b: semantic if b == "semantic" else PlannedTask(train[b], needs[b], share) for b in branches}
    first = ["semantic"] if "semantic" in branches else [b for b in branches if b == "geometric"]
    lanes: list[list[PlannedTask]] = [[planned[b] for b in first], [planned[b] for b in branches if b not in first]]
    everything = tuple(train.values())
    without_semantic = tuple(train[b] for b in branches if b != "semantic")
    for proposals in bench:
        if proposals is Proposals.SEMANTIC:
            lanes[0].append(PlannedTask(BENCH_TASKS[proposals], everything, share))
        else:
            lanes[1 if "semantic" in branches else 0].append(PlannedTask(BENCH_TASKS[proposals], without_semantic,
                                                                         share))
    lanes[1].append(PlannedTask(EDITS_TASK, everything, share))
    return lanes


def _lane_task_command(spec: dict, work: Path, name: str) -> list[str]:
    import json

    path = work / f"{name}.json"
    path.write_text(json.dumps(spec), encoding="utf-8")
    return [sys.executable, "-m", "sdn3d.cli._demo_task", str(path)]


def lane_tasks(plan: list[list[PlannedTask]], cfg: Any, data_root: Path, out: Path) -> list[list]:
    """:func:`lane_plan`'s tasks as :class:`sdn3d.cli._lanes.LaneTask` children of ``cfg``, each with the torch threads
    its plan gives it (``threads=``, ``OMP_NUM_THREADS``, a training's ``later`` as its ``threads_later``):
    ``sdn3d-train`` runs (output in ``runs/<branch>.out``),
    the benchmark's passes and the edits (``python -m sdn3d.cli._demo_task``, output in ``logs/bench_predicted.out``,
    ``logs/bench_oracle.out`` and ``logs/edits.out``; the
    benchmark is written from both passes by :func:`run_bench` once they ended)."""
    import pickle

    from sdn3d.cli._lanes import LaneTask

    runs, logs = out / "runs", out / "logs"
    runs.mkdir(parents=True, exist_ok=True)
    logs.mkdir(parents=True, exist_ok=True)

    def checkpoints(done: dict) -> dict[str, str]:
        return {b: _checkpoint(done[_train_name(b)]) for b in cfg.train.branches if _train_name(b) in done}

    def training(branch: str, task_cfg: Any, later: ThreadsLater | None) -> LaneTask:
        run_dir, log, started = runs / branch, runs / f"{branch}.out", {}

        def start(done: dict) -> subprocess.Popen:
            _set_aside(run_dir)
            upstream = checkpoints(done) if branch == "textural" else None
            started["t"] = time.perf_counter()
            with open(log, "w") as stream:
                return subprocess.Popen(_train_command(branch, task_cfg, data_root, runs, upstream, True, later),
                                        env=_train_env(task_cfg), stdout=stream, stderr=subprocess.STDOUT)

        def finish(code: int, done: dict) -> dict:
            return _finish(branch, run_dir, code, started["t"], _keep_or_restore(run_dir))

        return LaneTask(_train_name(branch), (), start, finish, log)

    def child(name: str, slug: str, steps: list[str], proposals: str | None, task_cfg: Any) -> LaneTask:
        log, result = logs / f"{slug}.out", logs / f"{slug}.result.pkl"
        container = OmegaConf.to_container(task_cfg, resolve=True)

        def start(done: dict) -> subprocess.Popen:
            result.unlink(missing_ok=True)
            spec = {"steps": steps, "config": container, "data_root": str(data_root), "checkpoints": checkpoints(done),
                    "output_dir": str(out), "proposals": proposals, "result": str(result)}
            with open(log, "w") as stream:
                return subprocess.Popen(_lane_task_command(spec, logs, slug), env=_train_env(task_cfg),
                                        stdout=stream, stderr=subprocess.STDOUT)

        def finish(code: int, done: dict) -> dict:
            (logs / f"{slug}.json").unlink(missing_ok=True)
            if code != 0:
                raise DemoStageError(f"its process ended with exit status {code}")
            with open(result, "rb") as stream:
                value = pickle.load(stream)
            result.unlink()
            return value

        return LaneTask(name, (), start, finish, log)

    predicted_row = any(t.name == BENCH_TASKS[Proposals.SEMANTIC] for lane in plan for t in lane)
    trainings = {_train_name(b): b for b in cfg.train.branches}
    bench_proposals_of = {name: proposals for proposals, name in BENCH_TASKS.items()}

    def made(planned: PlannedTask) -> LaneTask:
        task_cfg = OmegaConf.merge(cfg, {"threads": planned.threads})
        if planned.name in trainings:
            task = training(trainings[planned.name], task_cfg, planned.later)
        elif planned.name == EDITS_TASK:  # the recall after the edits: each step's results are the same in either
            task = child(EDITS_TASK, "edits", ["edits"] + (["recall"] if predicted_row else []), None, task_cfg)
        else:
            proposals = bench_proposals_of[planned.name]
            slug = "bench_predicted" if proposals is Proposals.SEMANTIC else "bench_oracle"
            task = child(planned.name, slug, ["bench"], proposals.value, task_cfg)
        return task._replace(needs=planned.needs)

    return [[made(planned) for planned in lane] for lane in plan]


def task_threads(planned: PlannedTask) -> dict[str, int]:
    """The report's record of a planned task's threads: ``{'threads': n}``, with ``'after_epochs'`` and ``'then'``
    for a training that takes more from an epoch on."""
    if planned.later is None:
        return {"threads": planned.threads}
    return {"threads": planned.threads, "after_epochs": planned.later.after_epochs, "then": planned.later.threads}


def threads_words(record: dict[str, int]) -> str:
    """``1 torch thread``, or ``1 torch thread for its first 7 epochs, then 2`` (a :func:`task_threads` record)."""
    n = record["threads"]
    words = f"{n} torch thread{'s' if n != 1 else ''}"
    if "then" in record:
        words += f" for its first {record['after_epochs']} epochs, then {record['then']}"
    return words


def threads_sentence(threads: dict[str, dict[str, int]]) -> str:
    """``training: semantic 1 torch thread for its first 7 epochs, then 2; every other stage 1 torch thread`` from
    ``{task: its task_threads record}`` (lane plan order): the tasks unlike most named; ``1 torch thread each`` when
    all are alike."""
    words = {task: threads_words(record) for task, record in threads.items()}
    counts = list(words.values())
    usual = max(counts, key=lambda w: (counts.count(w), -len(w)))  # the most common wording; on a tie, the shortest
    named = [f"{task} {w}" for task, w in words.items() if w != usual]
    if not named:
        return f"{usual} each"
    return f"{'; '.join(named)}; every other stage {usual}"


def run_in_lanes(cfg: Any, root: Path, out: Path, info: dict, started: float) -> dict[str, str]:
    """Training, benchmark and edits in ``lanes`` concurrent processes (:func:`lane_plan`); fills ``info``
    (``training``, ``proposal_recall``, ``bench``, ``edits``, ``lanes``, ``stages_s``) and returns the
    checkpoints.

    Raises:
        DemoStageError: naming the stage that failed and its log (the other lane's running stage stopped).
    """
    from sdn3d.cli._lanes import LaneError, run_lanes

    branches = [str(b) for b in cfg.train.branches]
    # the benchmark's passes as bench_proposals gives them, had every branch trained
    sources = bench_proposals(cfg, {b: "planned" for b in branches})
    plan = lane_plan(branches, "textural" in branches and _textural_needs_upstream(cfg), sources, int(cfg.threads),
                     cfg.semantic_threads_after_epochs)
    threads = {t.name: task_threads(t) for lane in plan for t in lane}
    _stage(f"2-4/4 training, benchmark and edits in {len(plan)} lanes ({threads_sentence(threads)}; "
           f"budget {cfg.budget_name})")
    t0 = time.perf_counter()
    try:
        done, timeline = run_lanes(lane_tasks(plan, cfg, root, out), started,
                                   lambda line: console.print(f"sdn3d-demo: {line}", markup=False))
    except LaneError as exc:
        raise DemoStageError(str(exc)) from exc
    info["training"] = {b: done[_train_name(b)] for b in branches}
    ckpts = {b: _checkpoint(s) for b, s in info["training"].items()}
    parts = [done[BENCH_TASKS[p]]["bench"] for p in sources]
    info["proposal_recall"] = done[EDITS_TASK].get("recall")
    t1 = time.perf_counter()
    bench = run_bench(cfg, root, ckpts, out / "bench", parts)  # both passes written as one benchmark
    info["bench"] = {"summary": bench["summary"], "info": bench["info"]}
    info["edits"] = done[EDITS_TASK]["edits"]
    ends = {row["task"]: row["end_s"] for row in timeline}
    trained = max((ends[_train_name(b)] for b in branches), default=t0 - started)
    info["stages_s"] |= {"train": round(trained - (t0 - started), 1),
                         "after_training": round(time.perf_counter() - started - trained, 1),
                         "bench_write": round(time.perf_counter() - t1, 1)}
    info["lanes"] = {"lanes": len(plan), "threads": threads,
                     "timeline": [{**row, "threads": threads[row["task"]]} for row in timeline]}
    return ckpts


def _checkpoint(summary: dict) -> str:
    path = summary.get("best_ckpt") or summary.get("last_ckpt")
    if not path:
        raise DemoStageError(f"run {summary.get('run_dir')} wrote no checkpoint")
    return str(path)


#: The proposals the demo's benchmark and example edits take: the semantic branch's (predicted) or the oracle's.
DEMO_PROPOSALS = (Proposals.SEMANTIC.value, Proposals.GT.value)


def _proposals(value: Any, key: str) -> Proposals:
    if not isinstance(value, str) or value not in DEMO_PROPOSALS:
        raise InputError(f"{key} must be one of {list(DEMO_PROPOSALS)}, got {value!r}")
    return Proposals(value)


class EditModes(NamedTuple):
    """The example edits' modes (``edits.*``) as their types: the one place they are read as strings."""

    appearance: Appearance
    compose: ComposeSettings
    proposals: Proposals
    photo: Any  # PhotoSettings


def edit_modes(cfg: Any) -> EditModes:
    """``edits.appearance``, ``edits.compose``, ``edits.proposals`` and ``edits.photo`` parsed.

    Raises:
        InputError (and the compose / photo settings' errors): naming the setting.
    """
    from sdn3d.editing.photo.settings import PhotoSettings

    edits = cfg.edits  # typed by the schema (sdn3d.cli._schemas.DemoSchema): strings, checked here as values
    if edits.appearance not in APPEARANCES:
        raise InputError(f"edits.appearance must be one of {list(APPEARANCES)}, got {edits.appearance!r}")
    return EditModes(Appearance(edits.appearance), ComposeSettings(edits.compose),
                     _proposals(edits.proposals, "edits.proposals"), PhotoSettings.from_mapping(edits.photo))


def bench_proposals(cfg: Any, ckpts: dict[str, str]) -> list[Proposals]:
    """``bench.proposals`` (predicted row first, then the oracle row), less the predicted row when no semantic
    branch was trained (``train.branches`` without it): the benchmark's table then says it has oracle rows only."""
    proposals = [_proposals(p, "bench.proposals") for p in cfg.bench.proposals]
    if Proposals.SEMANTIC in proposals and not ckpts.get("semantic"):
        console.print("[yellow]sdn3d-demo: no semantic branch was trained: the benchmark has only the oracle row "
                      "(ground-truth masks and semantics)[/yellow]")
        proposals = [p for p in proposals if p is not Proposals.SEMANTIC] or [Proposals.GT]
    return proposals


def bench_config(cfg: Any, data_root: Path, ckpts: dict[str, str], out: Path,
                 proposals: Sequence[Proposals] | None = None) -> Any:
    """The ``sdn3d-bench`` config of the demo's benchmark (``proposals``: its passes; None: :func:`bench_proposals`)."""
    from sdn3d.cli._config import compose_config

    proposals = bench_proposals(cfg, ckpts) if proposals is None else proposals
    overrides = [f"data.root={data_root.resolve()}", f"data.image_size={render_size(cfg)}",
                 f"checkpoints.geometric={ckpts['geometric']}", f"checkpoints.textural={ckpts['textural']}",
                 f"checkpoints.semantic={ckpts.get('semantic')}" if ckpts.get("semantic") else
                 "checkpoints.semantic=null", f"proposals=[{','.join(proposals)}]",
                 f"examples={int(cfg.bench.examples)}", f"output_dir={out}", f"device={cfg.device}",
                 f"threads={int(cfg.threads)}"]
    if cfg.bench.limit is not None:
        overrides.append(f"limit={int(cfg.bench.limit)}")
    return compose_config(overrides, "bench")


def run_bench(cfg: Any, data_root: Path, ckpts: dict[str, str], out: Path, parts: Sequence[dict] = ()) -> dict:
    """The editing benchmark into ``out`` (``parts``: its passes already evaluated by the lanes'
    processes, :func:`sdn3d.cli.bench.evaluate_bench`; only written here)."""
    from sdn3d.cli.bench import run_bench as bench_main

    return bench_main(bench_config(cfg, data_root, ckpts, out), parts)


def run_proposal_recall(cfg: Any, data_root: Path, ckpts: dict[str, str]) -> dict | None:
    """How many of the test part's cars and vans (over 256 visible pixels) the semantic branch's proposals find
    at IoU >= 0.5, de-rendering at :func:`render_size` (:mod:`sdn3d.evaluation.proposal_recall`); None without
    a semantic run."""
    if not ckpts.get("semantic"):
        return None
    from sdn3d.cli._config import synth_data_source
    from sdn3d.data.sources import load_split
    from sdn3d.evaluation.proposal_recall import PAPER_MIN_PIXELS, predictor_recall
    from sdn3d.semantic.predict import SemanticPredictor

    source = synth_data_source(data_root)
    size = render_size(cfg)
    predictor = SemanticPredictor.from_checkpoint(ckpts["semantic"], map_location=str(cfg.device),
                                                  image_size=(int(size[0]), int(size[1])))
    counts, _ = predictor_recall(load_split(source, "test"), predictor, PAPER_MIN_PIXELS)
    names = {c.id: c.name for c in source.class_list}
    return {**counts.summary(names), "min_pixels": PAPER_MIN_PIXELS, "iou": 0.5, "work_size": list(size)}


def render_size(cfg: Any) -> list[int]:
    """``[W, H]`` the benchmark and the example edits work at: ``render_size``, else the data's size.

    The textural generator draws best at the size it was trained at (the short budget trains it at half
    size); frames are resized to it and the intrinsics with them.
    """
    size = cfg.get("render_size") or cfg.synth.image_size
    return [int(size[0]), int(size[1])]


def _pick_frame(records: Sequence[Any], size: tuple[int, int], wanted: str | None):
    if wanted:
        for r in records:
            if r.key == wanted or r.key.endswith(str(wanted)):
                return r
        raise InputError(f"edits.frame={wanted!r} is not a test frame; e.g. {records[0].key}")

    def nearest_car(r) -> float:  # a car wholly in the picture: the edits show it whole
        zs = [o.location[2] for o in r.objects if o.label in ("Car", "Van") and o.location[2] > 3 and o.truncr == 0]
        return -min(zs) if zs else -1e9

    return max(records, key=nearest_car)


def run_edits(cfg: Any, data_root: Path, ckpts: dict[str, str], out: Path) -> dict:
    """De-render one test frame and render a series of 3D edits of one car (on the semantic branch's proposals: the
    largest found car wholly in view over the test frames, :func:`_found_example`; else the frame with the nearest
    car wholly in view and its largest car), in
    ``edits.appearance`` (``photo``: the frame's own pixels through each car's 3D shape at the frame's resolution;
    ``generator``: the textural generator, composed by ``edits.compose``: ``edited`` puts each edit into the frame
    at its own resolution, ``full`` shows the generator's picture). The grid's panels are titled."""
    from sdn3d.cli._config import synth_data_source
    from sdn3d.data.frames import load_frame
    from sdn3d.data.records import load_rgb
    from sdn3d.data.scene_gt import frame_photo, ground_truth
    from sdn3d.data.sources import load_split
    from sdn3d.derender import PROPOSAL_LABELS, Models, derender
    from sdn3d.editing.frame import PixelFrame
    from sdn3d.geometric.fit import FitSettings
    from sdn3d.io import write_png_atomic
    from sdn3d.scene.io import save_scene
    from sdn3d.visualize import titled_row

    appearance, compose, wanted, photo = edit_modes(cfg)
    source = synth_data_source(data_root, render_size(cfg))
    records = [r for r in load_split(source, "test") if r.objects]
    predicted = wanted is Proposals.SEMANTIC and bool(ckpts.get("semantic"))
    distrust = _semantic_distrust(ckpts.get("semantic"), data_root) if predicted else []
    predicted = predicted and not distrust
    models = Models.from_checkpoints(ckpts["semantic"] if predicted else None, ckpts["geometric"], ckpts["textural"],
                                     map_location=str(cfg.device))
    found = _found_example(records, source, models, str(cfg.device)) if predicted and not cfg.edits.frame else None
    record = found[0] if found else _pick_frame(records, source.image_size, cfg.edits.frame)
    frame = load_frame(record, source.image_size, semantic=True, instances=True)
    started = time.perf_counter()
    gt = ground_truth(record, (frame.intrinsics.width, frame.intrinsics.height))
    fit = FitSettings()  # the proposals' test-time fit, as sdn3d-edit's fit_proposals=true gives a user
    stored = frame_photo(record, source.image_size)  # the geometric branch's crops read from the frame as stored
    scene = derender(frame.image.to(cfg.device), frame.intrinsics, models,
                     Proposals.SEMANTIC if predicted else Proposals.GT, gt, fit=fit, photo=stored)
    proposals = PROPOSAL_LABELS[Proposals.SEMANTIC] if predicted else \
        PROPOSAL_LABELS[Proposals.GT] + (f" ({'; '.join(distrust)})" if distrust else "")
    if predicted and not bool(scene.objects.has_geometry.any()):
        scene = derender(frame.image.to(cfg.device), frame.intrinsics, models, Proposals.GT, gt, fit=fit, photo=stored)
        proposals = PROPOSAL_LABELS[Proposals.GT] + " (the semantic branch found no car with 3D geometry on this frame)"
    derender_s = time.perf_counter() - started
    car, edits, recoloured = _example_edits(cfg, scene, record.key, ckpts["textural"], appearance,
                                            found[1] if found else None)
    original = np.ascontiguousarray(load_rgb(record), dtype=np.uint8)
    transform = PixelFrame((original.shape[1], original.shape[0]), tuple(source.image_size))
    pictures, timings = _edit_pictures(edits, scene, models, compose, original, transform, out, appearance, photo)
    at_input = appearance is Appearance.PHOTO or compose.mode is Compose.EDITED
    source_rgb = original if at_input else _uint8_picture(frame.image)
    write_png_atomic(out / "source.png", source_rgb)
    names = list(pictures)
    how = "photo appearance" if appearance is Appearance.PHOTO else f"generator, compose {compose.mode}"
    # A figure drawn from the frame's own masks says so on its first panel, not only in the report (the oracle
    # stands in where the semantic branch is not trusted or finds no car: an Intel machine's short run, session 37).
    oracle = "; objects: oracle, ground-truth masks" if proposals.startswith(PROPOSAL_LABELS[Proposals.GT]) else ""
    titled = [(f"source: {record.key}, car {car}{oracle}", source_rgb)] + [(f"{name} ({how})", pictures[name])
                                                                           for name in names]
    blank = np.full_like(source_rgb, 255)  # an odd count of panels leaves the last row half empty
    rows = [titled_row([a, b if b is not None else ("", blank)]) for a, b in zip_longest(titled[0::2], titled[1::2])]
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    write_png_atomic(out / "edits_grid.png", grid)
    save_scene(scene, out / "scene")
    return {"frame": record.key, "car": car, "edits": names, "derender_s": round(derender_s, 3),
            "edit_render_s": timings, "grid": "edits/edits_grid.png", "grid_layout": ["source"] + names,
            "grid_titles": [title for title, _ in titled],
            "appearance": appearance, "compose": compose.mode, "recoloured": recoloured, "proposals": proposals,
            "picture_size": [int(source_rgb.shape[1]), int(source_rgb.shape[0])]}


def wholly_in_view(masks: torch.Tensor) -> torch.Tensor:
    """``(N,)`` bool: which of the masks ``(N, H, W)`` stay off the picture's left, right and bottom edges (an object
    the image does not cut; the top edge is sky)."""
    return ~(masks[:, :, 0].any(1) | masks[:, :, -1].any(1) | masks[:, -1, :].any(1))


#: :func:`_found_example`: the most of a proposal's pixels that may belong to other annotated objects. A proposal
#: that merged its car with a piece of the next one drags that piece along in every edit of the figure (session 5's
#: demo: a tan car's fragment smeared across the road by every edit of the blue example car).
EXAMPLE_MAX_FOREIGN = 0.05


def _found_example(records: Sequence[Any], source: Any, models: Any, device: str) -> tuple[Any, int] | None:
    """``(frame record, instance id)`` of the example edits on the semantic branch's proposals: over the test
    frames, the largest proposal with 3D geometry that is wholly in the picture (its mask off the left, right and
    bottom edges), that found a car wholly in view (IoU >= 0.5 with an annotated car or van that the image does
    not cut: the proposal-recall measure) and that took in no more than :data:`EXAMPLE_MAX_FOREIGN` of its pixels
    from other annotated objects (no merged neighbour); of equal ones, the first in ``records``' order. The
    annotation only chooses which found car the figure shows; the scene, its masks and its geometry are the
    branches' own. None where the proposals found no such car.

    Only the frames that could still hold a larger one are de-rendered: a mask at IoU >= 0.5 with a car covers at
    most twice the car's pixels, so the frames are searched by that bound, largest first, and the search stops at
    the first whose bound is below the best found (the same choice as de-rendering every frame; the demo's test
    part: a few frames of its 80 instead of all)."""
    import dataclasses

    from sdn3d.data.frames import load_frame
    from sdn3d.data.scene_gt import frame_photo, ground_truth
    from sdn3d.derender import derender
    from sdn3d.labels import INSTANCE_DIVISOR

    # The search reads masks and geometry only: without the textural branch derender skips pooling texture codes.
    search = dataclasses.replace(models, textural=None)
    candidates = []  # (area bound, order in records, record, frame, annotated track ids, [each whole car's pixels])
    for order, record in enumerate(records):
        untruncated = {o.track_id + 1 for o in record.objects if o.label in ("Car", "Van") and o.truncr == 0}
        if not untruncated:
            continue
        frame = load_frame(record, source.image_size, semantic=True, instances=True)
        annotated = (frame.instances % INSTANCE_DIVISOR) * (frame.instances >= INSTANCE_DIVISOR)  # 0: none
        truths = [annotated == k for k in sorted(untruncated)]
        bound = 2 * max(int(t.sum()) for t in truths)
        candidates.append((bound, order, record, frame, annotated, truths))
    candidates.sort(key=lambda c: (-c[0], c[1]))
    best: tuple[int, int, Any, int] | None = None  # (area, order in records, record, instance id)
    for bound, order, record, frame, annotated, truths in candidates:
        if best is not None and bound < best[0]:
            break  # no frame left can hold a larger one
        gt = ground_truth(record, (frame.intrinsics.width, frame.intrinsics.height))
        table = derender(frame.image.to(device), frame.intrinsics, search, "semantic", gt,
                         photo=frame_photo(record, source.image_size)).objects
        mask = table.mask.bool().cpu()
        for row in (table.has_geometry.cpu() & wholly_in_view(mask)).nonzero().flatten().tolist():
            area = int(mask[row].sum())
            if best is not None and (area, -order) <= (best[0], -best[1]):
                continue
            for truth in truths:
                union = int((truth | mask[row]).sum())
                foreign = int((mask[row] & ~truth & (annotated > 0)).sum())
                if union and int((truth & mask[row]).sum()) >= 0.5 * union and foreign <= EXAMPLE_MAX_FOREIGN * area:
                    best = (area, order, record, int(table.instance_id[row]))
                    break
    return (best[2], best[3]) if best is not None else None


def _semantic_distrust(checkpoint: str | None, data_root: Path | None = None) -> list[str]:
    """Why the semantic run of ``checkpoint`` is too weak to propose the example edits' objects (its recorded
    validation quality: :func:`sdn3d.runs.quality_warnings`, the edited frame read from ``data_root``); empty:
    trusted. The short budget's branch is."""
    import json

    from sdn3d.runs import quality_warnings, semantic_summary

    path = semantic_summary({"path": checkpoint, "from": "demo"}) if checkpoint else None
    if path is None:
        return []
    return quality_warnings(json.loads(path.read_text()).get("metrics"), None, str(path), data_root)


def _uint8_picture(image: torch.Tensor) -> np.ndarray:
    """``(3, H, W)`` float in [0, 1] -> ``(H, W, 3)`` uint8."""
    return (image.detach().cpu().clamp(0, 1).permute(1, 2, 0).numpy() * 255).round().astype(np.uint8)


def _example_edits(cfg: Any, scene: Any, key: str, textural: Path, appearance: Appearance = Appearance.PHOTO,
                   car: int | None = None) -> tuple[int, dict[str, list], str]:
    """``(car, {name: ops}, how it was recoloured)``: ``car`` (else the largest car with geometry wholly in the
    picture, else the largest) moved closer, rotated, recoloured (photo appearance: its body repainted
    ``edits.recolor``; generator: the code bank's code nearest that colour, a random code when the textural run
    wrote no bank), deleted. The photo appearance has no reconstruction (it would be the frame itself)."""
    from sdn3d.editing.apply import Delete, Rotate, SetCode, Zoom
    from sdn3d.labels import INSTANCE_DIVISOR
    from sdn3d.textural.code_bank import code_bank_path, load_code_bank, named_color

    table = scene.objects
    has_geo = table.has_geometry
    if not bool(has_geo.any()):
        raise DemoStageError(f"no object of {key} got 3D geometry")
    # The largest car wholly in the picture (its mask off the left, right and bottom edges), else the largest: the
    # one the edits show best. By its visible area, not its predicted depth: a short geometric branch can put a
    # small far car nearest.
    mask = table.mask.bool()
    whole = has_geo & wholly_in_view(mask)
    pick = whole if bool(whole.any()) else has_geo
    area = mask.flatten(1).sum(1).float()
    chosen = int(torch.where(pick, area, torch.full_like(area, -1.0)).argmax()) if car is None else \
        table.index_of(car)
    car = int(table.instance_id[chosen])
    others = [int(i) for i, g in zip(table.instance_id.tolist(), has_geo.tolist(), strict=True) if g and i != car]
    bank_file = code_bank_path(textural)
    colour = str(cfg.edits.recolor)
    paint = named_color(colour, "edits.recolor")
    if appearance is Appearance.PHOTO:
        new_code = table.code[chosen]
        recolour = f"{colour} (the car's body repainted, its shading and details kept)"
    elif bank_file.is_file():
        rgb = torch.tensor(named_color(colour, "edits.recolor"))
        new_code, _ = load_code_bank(bank_file, "the textural run's code bank").nearest(car // INSTANCE_DIVISOR, rgb)
        recolour = f"{colour} (the code bank's nearest code)"
    else:
        gen = torch.Generator().manual_seed(int(cfg.seed))
        new_code = torch.randn(scene.code_dim, generator=gen) * float(table.code.std().clamp_min(0.5))
        recolour = "a random code (the textural run wrote no code bank)"
    edits: dict[str, list] = {} if appearance is Appearance.PHOTO else {"reconstruction": []}
    edits[f"closer (zoom {cfg.edits.zoom})"] = [Zoom(car, float(cfg.edits.zoom), on_ground=True)]
    for angle in cfg.edits.angles_deg:
        edits[f"rotated {int(angle):+d} deg"] = [Rotate(car, float(np.deg2rad(angle)))]
    edits[f"recoloured {colour}"] = [SetCode(car, tuple(new_code.tolist()), paint)]
    edits["deleted"] = [Delete(car)]
    if others:
        edits["another car deleted"] = [Delete(others[0])]
    return car, edits, recolour


def _edit_pictures(edits: dict[str, list], scene: Any, models: Any, compose: Any, original: np.ndarray,
                   transform: Any, out: Path, appearance: Appearance = Appearance.PHOTO,
                   photo: Any = None) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    """``({name: (H, W, 3) uint8}, {name: seconds})``: each edit applied and drawn (timed) by the appearance
    (:func:`sdn3d.editing.appearance.appearance_renderer`, one source state for all), written as ``<name>.png``.
    Photo: at the frame's resolution, where each pixel came from in ``sources/<name>.png``. Generator: composed by
    ``compose``, the generator's own picture as ``generated/<name>.png``; the reconstruction (no edit) is the
    generator's picture, upsampled to the frame's size with ``compose='edited'``."""
    from sdn3d.editing.appearance import appearance_renderer
    from sdn3d.editing.apply import apply_edits
    from sdn3d.editing.photo.settings import source_picture
    from sdn3d.image_ops import resize_image
    from sdn3d.io import write_png_atomic

    original_t = torch.from_numpy(original).permute(2, 0, 1)
    renderer = appearance_renderer(appearance, photo=photo, compose=compose, textural=models.textural)
    state = renderer.prepare(original_t, transform, scene)
    pictures, timings = {}, {}
    for name, ops in edits.items():
        slug = name.split(" (")[0].replace(" ", "_").replace("+", "p").replace("-", "m")
        t0 = time.perf_counter()
        drawn = renderer.draw(state, apply_edits(scene, ops), ops)
        timings[name] = round(time.perf_counter() - t0, 3)
        if drawn.photo is not None:  # where each pixel came from
            pictures[name] = drawn.image.permute(1, 2, 0).numpy()
            write_png_atomic(out / f"{slug}.png", pictures[name])
            write_png_atomic(out / "sources" / f"{slug}.png", source_picture(drawn.photo.source))
            continue
        generated = drawn.generated.detach().cpu()
        if ops and compose.mode is Compose.EDITED:
            pictures[name] = drawn.image.permute(1, 2, 0).numpy()
        else:  # the reconstruction shows the generator (composing nothing would give the frame itself)
            size = tuple(transform.input_size) if compose.mode is Compose.EDITED else tuple(transform.working_size)
            pictures[name] = _uint8_picture(resize_image(generated, size))
        write_png_atomic(out / f"{slug}.png", pictures[name])
        if drawn.generated is not None:
            write_png_atomic(out / "generated" / f"{slug}.png", _uint8_picture(generated))
    return pictures, timings


def _training_rows(training: dict) -> str:
    """One markdown row per branch: wall time, steps and its test metrics (not the per-class ones)."""
    rows = []
    for branch, summary in training.items():
        metrics = {k[5:]: v for k, v in sorted(summary.get("metrics", {}).items())
                   if k.startswith("test/") and not k.startswith(("test/iou_", "test/pq_", "test/sq_", "test/rq_",
                                                                  "test/template_prob/"))}
        text = ", ".join(f"{k} {v:.4g}" for k, v in metrics.items()) or "n/a"
        rows.append(f"| {branch} | {summary.get('demo_wall_s')} | {summary.get('global_step')} | {text} |")
    return "\n".join(rows)


def _compose_note(edits: dict) -> str:
    """What the example edits' pictures are (``edits.appearance``, ``edits.compose``)."""
    size = "x".join(str(v) for v in edits.get("picture_size", []))
    if edits.get("appearance") == Appearance.PHOTO:
        return (f"Photo appearance: each edit at the frame's {size} resolution, the car drawn with the frame's own "
                "pixels through its 3D shape (hidden sides from its mirror image, then its body colour), the road it "
                "left inpainted; `edits/sources/` shows where each pixel came from (dark grey input, green photo, "
                "blue mirror, red fallback, yellow inpainted, violet repainted, grey new shadow).")
    if edits.get("compose") == Compose.EDITED:
        return (f"Compose *edited*: each edit is put into the frame at its own {size} resolution, only the edited "
                "region redrawn by the generator, every other pixel the frame's; the reconstruction is the "
                "generator's whole picture, upsampled; `edits/generated/` holds the generator's pictures.")
    return f"Compose *full*: the generator's whole pictures at {size} (the paper's protocol)."


def _recall_note(recall: dict | None) -> str:
    """One sentence on the predicted row's proposals: the semantic branch's recall of the test part's vehicles."""
    if not recall:
        return "No semantic branch was trained: every row below runs on ground-truth proposals (oracle)."
    per = ", ".join(f"{name} {v['recall']:.2f} of {v['objects']}" for name, v in recall.get("per_class", {}).items())
    return (f"The semantic branch's proposals (the predicted rows' objects) find **{recall['recall']:.2f}** of the "
            f"test part's {recall['objects']} vehicles over {recall['min_pixels']} visible pixels (IoU >= "
            f"{recall['iou']}; {per}; {recall['proposals']} proposals, precision {recall['precision']:.2f}). "
            "A vehicle without a proposal cannot be edited and is drawn as background in the predicted rows.")


def precision_note(info: dict) -> str:
    """Why the report gives the semantic branch's proposal precision more than once, with different values: three
    parts and two object filters, named."""
    sem = (info.get("training") or {}).get("semantic") or {}
    m = sem.get("metrics") or {}
    recall = info.get("proposal_recall") or {}
    figures = []
    if isinstance(m.get("val/proposal_precision"), (int, float)):
        figures.append(f"{m['val/proposal_precision']:.3f} on the **validation** part at the training size, objects "
                       "over the paper's 256 pixels scaled to that size (what decides whether `sdn3d-edit` trusts "
                       "the branch)")
    if isinstance(m.get("test/proposal_precision"), (int, float)):
        figures.append(f"{m['test/proposal_precision']:.3f} on the **test** part with the same measure (the training "
                       "table)")
    if recall.get("precision") is not None:
        size = "x".join(str(v) for v in recall.get("work_size", []))
        figures.append(f"{recall['precision']:.3f} on the **test** part at the edits' {size}, objects over "
                       f"{recall.get('min_pixels')} pixels at that size (what the edits meet; the sentence above)")
    if len(figures) < 2:
        return ""
    return ("Proposal precision appears more than once because it is measured on different parts and filters: "
            + "; ".join(figures) + ".")


_EMPTY_CELLS = ("n/a", "")


def _cells(line: str) -> list[str]:
    """The cells of a markdown table row (a ``\\|`` inside a cell is not a separator)."""
    return [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]


def drop_empty_columns(markdown: str) -> str:
    """``markdown`` with every table column whose body cells are all ``n/a`` (or blank) left out: a column without
    values (e.g. LPIPS without its weights, an objects' PSNR of deletions) says nothing. Other lines unchanged."""
    lines = markdown.split("\n")
    out: list[str] = []
    i = 0
    while i < len(lines):
        if not lines[i].lstrip().startswith("|"):
            out.append(lines[i])
            i += 1
            continue
        j = i
        while j < len(lines) and lines[j].lstrip().startswith("|"):
            j += 1
        rows = [_cells(line) for line in lines[i:j]]
        body = rows[2:] if len(rows) > 2 and all(re.fullmatch(r":?-+:?", c) for c in rows[1]) else []
        width = len(rows[0])
        keep = [k for k in range(width) if not body or any(k < len(r) and r[k] not in _EMPTY_CELLS for r in body)]
        if len(keep) == width:
            out += lines[i:j]
        else:
            kept = [[r[k] if k < len(r) else "" for k in keep] for r in rows]
            out += ["| " + " | ".join(r) + " |" if n != 1 or not body else "|" + "---|" * len(keep)
                    for n, r in enumerate(kept)]
        i = j
    return "\n".join(out)


def _table1_parts(table1: str) -> tuple[str, str]:
    """``(headline, rest)`` of the benchmark's table1.md: its ``# Editing benchmark: headline`` section (less the
    heading) and everything after it, headings two levels down (they sit under the report's ``##``)."""
    head, rest = "", table1
    match = re.match(r"# Editing benchmark: headline\n(.*?)(?=^# )", table1, re.S | re.M)
    if match:
        head, rest = match.group(1).strip(), table1[match.end():]
    rest = re.sub(r"^(#+) ", lambda m: "#" * (len(m.group(1)) + 2) + " ", rest, flags=re.M)
    return head, rest.strip()


def _floor_phrase(value: float, floor: float, name: str) -> str:
    relation = "under" if value < floor else "at" if value == floor else "over"
    return f"{relation} its {name} {floor:.3f}"


def branch_lines(training: dict, recall: dict | None) -> list[str]:
    """One line per trained branch for the report's first screen: its headline test figure beside the floor or bar
    its run recorded (the geometric branch's mesh accuracy beside the majority / uniform floors and the
    identifiability ceiling; the semantic branch's PQ, its validation proposal recall and precision beside the bar
    they need to be trusted, :data:`sdn3d.runs.MIN_PROPOSAL_RECALL` (a run without them: its validation PQ beside
    :data:`sdn3d.runs.MIN_VEHICLE_PQ`), and its proposals' test recall); the textural branch records none, which
    is said."""
    from sdn3d.runs import MIN_PROPOSAL_RECALL, MIN_VEHICLE_PQ, proposals_trusted, recorded_pq, recorded_proposals

    out = []
    for branch, summary in training.items():
        m = summary.get("metrics") or {}

        def num(key: str, m: dict = m) -> float | None:
            v = m.get(key)
            return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) and v == v else None

        lead = f"- **{branch}** ({summary.get('global_step')} steps, {summary.get('demo_wall_s')} s):"
        if branch == "semantic":
            parts = [f"test mIoU {num('test/miou'):.3f}"] if num("test/miou") is not None else []
            test_pq, val_pq = recorded_pq(m, "test"), recorded_pq(m, "val")
            if test_pq is not None:
                parts.append(f"test {test_pq[0]} {test_pq[1]:.3f}")
            val_proposals = recorded_proposals(m)
            if val_proposals is not None:
                trusted = "trusted" if proposals_trusted(val_proposals) else "not trusted"
                parts.append(f"validation proposal recall {val_proposals[0]:.3f} and precision {val_proposals[1]:.3f} "
                             f"against the {MIN_PROPOSAL_RECALL} each needs to be trusted ({trusted})")
            elif val_pq is not None:
                trusted = "trusted" if val_pq[1] >= MIN_VEHICLE_PQ else "not trusted"
                parts.append(f"validation {val_pq[0]} {val_pq[1]:.3f} against the {MIN_VEHICLE_PQ} its proposals "
                             f"need to be trusted ({trusted})")
            if recall:
                found = round(recall["recall"] * recall["objects"])
                parts.append(f"its proposals find {found} of the test part's {recall['objects']} vehicles (recall "
                             f"{recall['recall']:.2f}, precision {recall['precision']:.2f})")
        elif branch == "geometric":
            parts = []
            acc, major = num("test/mesh_accuracy"), num("test/mesh_majority_floor")
            if acc is not None:
                floors = [_floor_phrase(acc, major, "majority floor")] if major is not None else []
                floors += [f"uniform {num('test/mesh_uniform_floor'):.3f}"] if num("test/mesh_uniform_floor") \
                    is not None else []
                floors += [f"identifiability ceiling {num('test/mesh_identifiability_ceiling'):.3f}"] if \
                    num("test/mesh_identifiability_ceiling") is not None else []
                parts.append(f"mesh accuracy {acc:.3f}" + (f" ({'; '.join(floors)})" if floors else ""))
            if num("test/orientation_similarity") is not None:
                parts.append(f"orientation similarity {num('test/orientation_similarity'):.3f}")
            if num("test/reprojection_error_image") is not None:
                parts.append(f"reprojection error {1e3 * num('test/reprojection_error_image'):.2f} x1e-3 "
                             "(Table 2's units)")
        elif branch == "textural":
            parts = [f"test PSNR {num('test/psnr'):.2f} dB"] if num("test/psnr") is not None else []
            parts += [f"L1 {num('test/l1'):.4f}"] if num("test/l1") is not None else []
            parts += [f"the objects' PSNR {num('test/obj_psnr'):.2f} dB"] if num("test/obj_psnr") is not None else []
            if parts:
                parts.append("no floor recorded (Table 1 below sets its edits beside the 2D baselines)")
        else:
            parts = []
        out.append(f"{lead} " + ("; ".join(parts) if parts else "no test figures recorded") + ".")
    return out


def _first_screen(info: dict, headline: str) -> str:
    """The report's first screen: the labelled before/after figure of the example edits, one line per branch,
    the headline rows of Table 1 (columns without values left out)."""
    edits = info.get("edits") or {}
    parts = ["# sdn3d demo report", ""]
    if edits.get("grid"):
        picture = Path(str(edits["grid"])).as_posix()  # relative to the output directory, where report.md is
        proposals = str(edits.get("proposals", ""))
        label, _, why = proposals.partition(" (")
        origin = f"objects from the {label}" + (" (why: *Example edits* below)" if why else "")
        size = "x".join(str(v) for v in edits.get("picture_size", []))
        parts += [f"![The demo's edits, before and after, each panel titled]({picture})", "",
                  f"*Frame `{edits.get('frame')}`, car {edits.get('car')} (the largest found wholly in view): "
                  f"{', '.join(edits.get('grid_layout', []))}; {edits.get('appearance', 'photo')} appearance at "
                  f"{size}; {origin}.*", ""]
    budget = info.get("budget", "short")
    short = "a short run that shows the system works, not what the method reaches; " if budget == "short" else ""
    parts += [f"**What each branch reached** on the test part (budget `{budget}` on {info.get('device')}, {short}the "
              "details follow below):", "", *branch_lines(info.get("training") or {}, info.get("proposal_recall")),
              ""]
    if headline:
        parts += ["**Table 1, headline** (the editing benchmark, `bench/table1.md`):", "", drop_empty_columns(headline),
                  ""]
    return "\n".join(parts)


def write_report(out: Path, info: dict) -> str:
    """Write ``report.md`` and ``summary.json`` (``info``) into ``out``; returns the report. Its first screen: the
    labelled before/after figure of the example edits, one line per branch (its figure beside its floor), Table 1's
    headline rows; the caveats and every table follow. Columns without values are left out
    (:func:`drop_empty_columns`). ``info`` is what :func:`run_demo` gathers (``summary.json``: the report can be
    written again from it)."""
    from sdn3d.io import write_json_atomic, write_text_atomic

    t = info["training"]
    table1_file = out / "bench" / "table1.md"
    headline, table1 = _table1_parts(table1_file.read_text()) if table1_file.is_file() else ("", "(not run)")
    edits = info.get("edits", {})
    rows = "\n".join(f"| {name} | {sec:.2f} |" for name, sec in edits.get("edit_render_s", {}).items())
    where = f"{info['device']}" + (f" ({info['gpu']})" if info.get("gpu") else f", {threads_phrase(info)}")
    memory = ("(largest child process: a training run, a benchmark pass or the edits), {:.0f} MiB (this process)"
              if info.get("lanes") else "(largest\n  training process), {:.0f} MiB (this process: benchmark and edits)")
    if info.get("budget", "short") == "short":
        kind = "CPU" if info["device"] == "cpu" else "GPU"
        intro = (f"**These numbers come from a short {kind} run** ({where}) on a small synthetic dataset with the "
                 "branches' `experiment=demo_short` budgets: they show that the whole system works end to end, not "
                 "what the method reaches.")
    else:
        intro = (f"**These numbers come from the `{info['budget']}` budget** on {where} "
                 f"(`conf/budget/{info['budget']}.yaml`): longer than the README's demo, still far shorter than "
                 "the paper's schedules, on synthetic data.")
    report = f"""{_first_screen(info, headline)}
---

## Details

{intro} The paper's configurations are `experiment=paper_vkitti|paper_cityscapes`.

- Data: {data_sentence(info['data'], info.get('seed'))}, every branch's training, validation and test parts;
  benchmark and edits at {info['data']['render_size'][0]}x{info['data']['render_size'][1]}
  (`{info['data']['root']}`), generated in {info['stages_s']['data']:.0f} s.
- Wall time {info['wall_s'] / 60:.1f} min; peak memory {info['peak_memory']['largest_child_mib']:.0f} MiB \
{memory.format(info['peak_memory']['demo_process_mib'])}.

## Time per stage

{machine_sentence(info)}

| stage | seconds |
|---|---|
{stage_rows(info)}

## Training (`{out / 'runs'}`, TensorBoard: `tensorboard --logdir {out / 'runs'}`)

| branch | wall s | steps | test metrics |
|---|---|---|---|
{_training_rows(t)}

## Editing benchmark (`bench/`: table1.md, index.html with example grids)

{_recall_note(info.get('proposal_recall'))}

{precision_note(info)}

{drop_empty_columns(table1)}

## Example edits (`edits/`)

Frame `{edits.get('frame')}`, car {edits.get('car')} (the largest found wholly in view), scene from
{edits.get('proposals', 'n/a')}:
`edits/edits_grid.png` holds, row by row,
{', '.join(edits.get('grid_layout', []))}. Recoloured: {edits.get('recoloured', 'n/a')}.
{_compose_note(edits)} De-rendering took {edits.get('derender_s', float('nan')):.2f} s.

| edit | edit + render + compose s |
|---|---|
{rows}
"""
    write_text_atomic(out / "report.md", report)
    write_json_atomic(out / "summary.json", info)
    return report


def data_record(root: Path) -> dict:
    """What the demo's synthetic dataset holds, for the report: its root, frame count (edit targets included) and, as
    its manifest records them, worlds, variations, frames per sequence and vehicles."""
    import json

    frames = sorted((root / "vkitti_1.3.1_rgb").rglob("*.png"))
    recorded = json.loads((root / "synth_manifest.json").read_text(encoding="utf-8")).get("config") or {}
    return {"root": str(root), "frames": len(frames),
            **{k: recorded[k] for k in ("worlds", "variations", "frames_per_sequence", "vehicles") if k in recorded}}


def data_sentence(data: dict, seed: Any) -> str:
    """``N synthetic frames at WxH (K worlds x [variations] x F frames, vehicles V, seed S)`` of a
    :func:`data_record` (with its ``image_size``); what every branch trained and was tested on."""
    size = "x".join(str(v) for v in data["image_size"])
    parts = []
    if data.get("worlds") and data.get("variations") and data.get("frames_per_sequence"):
        parts.append(f"{len(data['worlds'])} worlds x [{', '.join(data['variations'])}] x "
                     f"{data['frames_per_sequence']} frames")
    if data.get("vehicles"):
        parts.append(f"vehicles {data['vehicles']}")
    parts.append(f"seed {seed}")
    return f"{data['frames']} synthetic frames at {size} ({', '.join(parts)})"


def run_demo(cfg: Any) -> dict:
    if int(cfg.lanes) not in (1, 2):  # lane_plan makes two lanes; a third would only thin the threads
        raise InputError(f"lanes must be 1 (one stage after another) or 2 (two concurrent lanes), got {cfg.lanes}")
    torch.manual_seed(int(cfg.seed))
    torch.set_num_threads(int(cfg.threads))
    out = Path(str(cfg.output_dir))
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    info: dict[str, Any] = {"seed": int(cfg.seed), "threads": int(cfg.threads), "device": str(cfg.device),
                            "budget": str(cfg.budget_name), "stages_s": {}, "training": {}}
    if str(cfg.device).startswith("cuda"):
        info["gpu"] = torch.cuda.get_device_name(torch.device(str(cfg.device)))
    info["machine"] = machine_record()

    if cfg.gpu_budget and cfg.device == "cpu":
        console.print(f"[yellow]sdn3d-demo: budget={cfg.budget_name} on the CPU takes many hours (see "
                      f"conf/budget/{cfg.budget_name}.yaml); it is meant for device=cuda.[/yellow]")
    _stage("1/4 synthetic data")
    t0 = time.perf_counter()
    root = make_data(cfg)
    info["data"] = {**data_record(root), "image_size": list(cfg.synth.image_size), "render_size": render_size(cfg)}
    info["stages_s"]["data"] = round(time.perf_counter() - t0, 1)

    if int(cfg.lanes) > 1 and not cfg.train.get("parallel"):
        run_in_lanes(cfg, root, out, info, started)
        return _finish_demo(out, info, started)
    ckpts: dict[str, str] = {}
    branches = [str(b) for b in cfg.train.branches]
    t0 = time.perf_counter()
    # 3D-SDN's order: the textural branch learns to render the semantic and geometric branches' outputs, so it
    # trains after them (in parallel mode too: the other branches at once, then the textural one).
    upstream_branches = [b for b in branches if b != "textural"]
    if cfg.train.get("parallel"):
        _stage(f"2/4 training {', '.join(upstream_branches)} at once (budget {cfg.budget_name})")
        info["training"] = train_parallel(upstream_branches, cfg, root, out / "runs")
    else:
        for i, branch in enumerate(upstream_branches):
            _stage(f"2/4 training the {branch} branch ({i + 1}/{len(branches)}, budget {cfg.budget_name})")
            info["training"][branch] = train_branch(branch, cfg, root, out / "runs")
    if "textural" in branches:
        upstream = {b: _checkpoint(s) for b, s in info["training"].items()}
        _stage(f"2/4 training the textural branch ({len(branches)}/{len(branches)}, budget {cfg.budget_name})")
        if cfg.train.get("parallel"):
            info["training"] |= train_parallel(["textural"], cfg, root, out / "runs", upstream)
        else:
            info["training"]["textural"] = train_branch("textural", cfg, root, out / "runs", upstream)
    ckpts = {b: _checkpoint(s) for b, s in info["training"].items()}
    info["stages_s"]["train"] = round(time.perf_counter() - t0, 1)

    _stage("3/4 editing benchmark: 3D-SDN vs 2D vs 2D+")
    t0 = time.perf_counter()
    info["proposal_recall"] = run_proposal_recall(cfg, root, ckpts)
    bench = run_bench(cfg, root, ckpts, out / "bench")
    info["bench"] = {"summary": bench["summary"], "info": bench["info"]}
    info["stages_s"]["bench"] = round(time.perf_counter() - t0, 1)

    _stage("4/4 example edits")
    t0 = time.perf_counter()
    info["edits"] = run_edits(cfg, root, ckpts, out / "edits")
    info["stages_s"]["edits"] = round(time.perf_counter() - t0, 1)
    return _finish_demo(out, info, started)


def _finish_demo(out: Path, info: dict, started: float) -> dict:
    info["wall_s"] = round(time.perf_counter() - started, 1)
    info["machine"]["load_average_end"] = _load_average()
    info["peak_memory"] = _peak_rss_mib()
    report = write_report(out, info)
    console.print(report)
    return info


def main(argv: Sequence[str] | None = None) -> int:
    """``sdn3d-demo [overrides...]``; returns the exit status."""
    from sdn3d.cli._config import compose_config
    from sdn3d.cli._errors import run_cli

    argv = list(sys.argv[1:] if argv is None else argv)

    def demo() -> int:
        cfg = compose_config(argv, "demo")
        console.print(OmegaConf.to_yaml(cfg))
        try:
            run_demo(cfg)
        except DemoStageError as exc:  # a stage failed for a reason it names (e.g. a training run's exit)
            print(f"sdn3d-demo: error: {exc}", file=sys.stderr)
            return 1
        return 0

    return run_cli("demo", demo)


if __name__ == "__main__":
    sys.exit(main())
