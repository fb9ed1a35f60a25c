"""``sdn3d-demo``'s lanes: the fixed plan of which process runs which stage, the runner's order and its failures."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

from sdn3d.cli._lanes import LaneError, LaneTask, check_plan, run_lanes
from sdn3d.proposals import Proposals

BOTH = [Proposals.SEMANTIC, Proposals.GT]


def test_the_short_budget_trains_the_semantic_branch_beside_the_other_two_then_shares_out_the_rest():
    from sdn3d.cli.demo import BENCH_TASKS, EDITS_TASK, PlannedTask, lane_plan
    from sdn3d.training.start import ThreadsLater

    plan = lane_plan(["semantic", "geometric", "textural"], False, BOTH, 2, 7)
    trained = ("training: semantic", "training: geometric", "training: textural")
    # every task one thread, except the semantic training (the critical path): both from its 8th epoch on
    assert plan == [
        [PlannedTask("training: semantic", (), 1, ThreadsLater(7, 2)),
         PlannedTask(BENCH_TASKS[Proposals.SEMANTIC], trained, 1)],
        [PlannedTask("training: geometric", (), 1), PlannedTask("training: textural", (), 1),
         PlannedTask(BENCH_TASKS[Proposals.GT], ("training: geometric", "training: textural"), 1),
         PlannedTask(EDITS_TASK, trained, 1)]]
    # the same arguments, the same plan: which lane runs what, with how many threads, never depends on timing
    assert lane_plan(["semantic", "geometric", "textural"], False, BOTH, 2, 7) == plan
    # from its start (0), never (None), four threads in all, one in all
    branches = ["semantic", "geometric", "textural"]
    assert lane_plan(branches, False, BOTH, 2, 0)[0][0] == PlannedTask(trained[0], (), 2)
    assert lane_plan(branches, False, BOTH, 2, None)[0][0] == PlannedTask(trained[0], (), 1)
    four = lane_plan(branches, False, BOTH, 4, 7)
    assert four[0][0] == PlannedTask(trained[0], (), 2, ThreadsLater(7, 4))
    assert {t.threads for lane in four for t in lane} == {2}
    assert {(t.threads, t.later) for lane in lane_plan(branches, False, BOTH, 1, 7) for t in lane} == {(1, None)}


def test_the_demo_gives_its_semantic_training_the_second_thread_for_its_second_half():
    """conf/demo.yaml: 2 threads, 2 lanes, the semantic training's second thread from epoch 8 of 14 (when the other
    lane, on an idle machine, is done with its stages); the report says so."""
    from sdn3d.cli._config import compose_config
    from sdn3d.cli.demo import lane_plan, task_threads, threads_phrase

    cfg = compose_config([], "demo")
    assert (cfg.threads, cfg.lanes, cfg.semantic_threads_after_epochs) == (2, 2, 7)
    plan = lane_plan(["semantic", "geometric", "textural"], False, BOTH, cfg.threads, cfg.semantic_threads_after_epochs)
    threads = {t.name: task_threads(t) for lane in plan for t in lane}
    assert threads["training: semantic"] == {"threads": 1, "after_epochs": 7, "then": 2}
    assert threads_phrase({"lanes": {"lanes": 2, "threads": threads}}) == (
        "2 lanes (training: semantic 1 torch thread for its first 7 epochs, then 2; every other stage 1 torch thread)")
    alike = {name: {"threads": 1} for name in threads}
    assert threads_phrase({"lanes": {"lanes": 2, "threads": alike}}) == "2 lanes (1 torch thread each)"


def test_a_textural_branch_on_predicted_maps_waits_for_both_upstream_branches():
    from sdn3d.cli.demo import EDITS_TASK, lane_plan

    plan = lane_plan(["semantic", "geometric", "textural"], True, BOTH, 2, 7)
    assert plan[1][1][:2] == ("training: textural", ("training: semantic", "training: geometric"))
    # without a semantic branch: lane 1 trains the geometric one and runs the oracle row, lane 2 the rest, every
    # task with its lane's share of the threads
    alone = lane_plan(["geometric", "textural"], False, [Proposals.GT], 2, 7)
    assert [(t.name, t.threads) for t in alone[0]] == [("training: geometric", 1), ("benchmark: oracle row", 1)]
    assert [(t.name, t.threads) for t in alone[1]] == [("training: textural", 1), (EDITS_TASK, 1)]


def test_the_medium_budget_is_recognised_as_training_on_predicted_maps():
    from sdn3d.cli._config import compose_config
    from sdn3d.cli.demo import _textural_needs_upstream

    assert not _textural_needs_upstream(compose_config([], "demo"))
    assert _textural_needs_upstream(compose_config(["budget=medium"], "demo"))


def _task(tmp_path: Path, name: str, code: str, needs: tuple[str, ...] = (), record: list | None = None) -> LaneTask:
    """A child running python ``code``; its result: the log's text; ``record`` collects (name, event) pairs."""
    log = tmp_path / f"{name}.out"

    def start(done: dict) -> subprocess.Popen:
        if record is not None:
            record.append((name, "start"))
        with open(log, "w") as stream:
            return subprocess.Popen([sys.executable, "-c", code], stdout=stream, stderr=subprocess.STDOUT)

    def finish(code_: int, done: dict) -> str:
        if record is not None:
            record.append((name, f"exit {code_}"))
        if code_ != 0:
            raise RuntimeError("child failed")
        return log.read_text().strip()

    return LaneTask(name, needs, start, finish, log)


def test_lanes_start_a_task_only_after_the_tasks_it_needs(tmp_path):
    events: list = []
    a = _task(tmp_path, "a", "import time; time.sleep(0.6); print('A')", record=events)
    b = _task(tmp_path, "b", "print('B')", needs=("a",), record=events)
    c = _task(tmp_path, "c", "print('C')", record=events)
    done, timeline = run_lanes([[a], [c, b]], say=lambda line: None)
    assert done == {"a": "A", "b": "B", "c": "C"}
    assert events.index(("b", "start")) > events.index(("a", "exit 0"))  # b waited for a, in the other lane
    assert {(r["lane"], r["task"]) for r in timeline} == {(1, "a"), (2, "c"), (2, "b")}


def test_a_failed_task_names_itself_and_its_log_and_stops_the_other_lane(tmp_path):
    events: list = []
    slow = _task(tmp_path, "slow", "import time; time.sleep(60)", record=events)
    bad = _task(tmp_path, "bad", "import sys; print('the reason'); sys.exit(3)", record=events)
    later = _task(tmp_path, "later", "print('never')", needs=("bad",), record=events)
    t0 = time.perf_counter()
    with pytest.raises(LaneError) as err:
        run_lanes([[slow], [bad, later]], say=lambda line: None)
    assert time.perf_counter() - t0 < 30  # the 60 s child was stopped, not waited for
    message = str(err.value)
    assert "bad failed (exit 3)" in message and str(tmp_path / "bad.out") in message and "the reason" in message
    assert "stopped meanwhile: slow" in message
    assert ("slow", "start") in events and any(n == "slow" and e.startswith("exit") for n, e in events)  # cleaned up
    assert ("later", "start") not in events


def test_a_killed_runner_stops_its_children(tmp_path):
    """``kill`` (SIGTERM) of the process running the lanes: it stops the running children before it exits."""
    import os
    import signal

    pid_file = tmp_path / "child.pid"
    runner = f"""
import subprocess, sys
from pathlib import Path
from sdn3d.cli._lanes import LaneTask, run_lanes
log = Path({str(tmp_path / 'child.out')!r})
def start(done):
    proc = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    Path({str(pid_file)!r}).write_text(str(proc.pid))
    return proc
run_lanes([[LaneTask("sleeper", (), start, lambda code, done: None, log)]], say=lambda line: None)
"""
    proc = subprocess.Popen([sys.executable, "-c", runner])
    for _ in range(200):
        if pid_file.is_file() and pid_file.read_text():
            break
        time.sleep(0.1)
    child = int(pid_file.read_text())
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=40) == 128 + signal.SIGTERM
    with pytest.raises(ProcessLookupError):  # stopped and reaped, not left running
        os.kill(child, 0)


def test_an_unsound_plan_is_refused_before_anything_starts(tmp_path):
    a = _task(tmp_path, "a", "pass", needs=("b",))
    b = _task(tmp_path, "b", "pass", needs=("a",))
    with pytest.raises(ValueError, match="can never start"):
        check_plan([[a], [b]])
    with pytest.raises(ValueError, match="no lane runs"):
        check_plan([[_task(tmp_path, "c", "pass", needs=("x",))]])
    with pytest.raises(ValueError, match="can never start"):  # needs one placed after it in its own lane
        check_plan([[_task(tmp_path, "d", "pass", needs=("e",)), _task(tmp_path, "e", "pass")]])


def test_the_demo_exits_1_naming_the_training_that_failed_in_a_lane(tmp_path, monkeypatch, capsys):
    """A failing ``sdn3d-train`` child in one lane: ``sdn3d-demo`` stops the other lane and exits 1, naming the
    stage and its output file; the earlier run of the branch is kept."""
    from sdn3d.cli import demo

    root = tmp_path / "data"
    root.mkdir()
    monkeypatch.setattr(demo, "make_data", lambda cfg: root)
    monkeypatch.setattr(demo, "data_record", lambda r: {"root": str(r), "frames": 0})

    def command(branch, cfg, data_root, runs, upstream=None, to_file=False, later=None):
        if branch == "semantic":
            return [sys.executable, "-c", "import sys; print('CUDA out of memory (stand-in)'); sys.exit(1)"]
        return [sys.executable, "-c", "import time; time.sleep(60)"]

    monkeypatch.setattr(demo, "_train_command", command)
    earlier = tmp_path / "out" / "runs" / "semantic"
    earlier.mkdir(parents=True)
    (earlier / "weights").write_text("earlier")
    t0 = time.perf_counter()
    status = demo.main([f"output_dir={tmp_path / 'out'}", f"data_dir={root}", "lanes=2"])
    assert status == 1 and time.perf_counter() - t0 < 40
    err = capsys.readouterr().err
    assert "sdn3d-demo: error: training: semantic failed (exit 1)" in err
    assert "runs/semantic.out" in err and "CUDA out of memory (stand-in)" in err
    assert "stopped meanwhile: training: geometric" in err
    assert (earlier / "weights").read_text() == "earlier"  # the failed run did not replace it


def test_the_benchmark_written_from_two_separately_evaluated_passes_equals_one_run(tiny_synth, tmp_path):
    """The lanes evaluate the predicted and the oracle pass in two processes; :func:`sdn3d.cli.bench.run_bench`
    then writes them: every entry's metrics, the summaries and the example grids as one run's."""
    from helpers.tiny_models import write_checkpoints

    from sdn3d.cli._config import compose_config
    from sdn3d.cli.bench import evaluate_bench, run_bench

    ckpts = write_checkpoints(tmp_path / "ckpts")

    def cfg(out: Path, proposals: str):
        return compose_config([f"data.root={tiny_synth}", "data.image_size=[160,64]", "compose=photo",
                               "geometric.crop_size=32", "geometric.min_pixels=1", "limit=2", "examples=1",
                               f"output_dir={out}", f"proposals={proposals}", "threads=1",
                               *(f"checkpoints.{b}={p}" for b, p in ckpts.items())], "bench")

    one = run_bench(cfg(tmp_path / "one", "[semantic,gt]"))
    parts = [evaluate_bench(cfg(tmp_path / "two", p)) for p in ("[gt]", "[semantic]")]  # in either order
    two = run_bench(cfg(tmp_path / "two", "[semantic,gt]"), parts)
    assert list(two["entries"]) == ["semantic", "gt"] == two["info"]["sources"]

    def same(a: object, b: object) -> bool:  # as JSON text: NaN (an empty region) equals NaN
        return json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)

    def metrics(report: dict) -> dict:
        return {s: [(r["metrics"], r["errors"]) for r in rows] for s, rows in report["entries"].items()}

    assert same(metrics(two), metrics(one)) and metrics(one)["gt"][0][0]  # (the tiny nets' predicted row may fail)
    assert same({s: v["methods"] for s, v in two["summary"].items()},
                {s: v["methods"] for s, v in one["summary"].items()})
    assert same(two["comparisons"], one["comparisons"])
    for name in one["outputs"]:
        if name.endswith(".png"):
            assert (tmp_path / "two" / name).read_bytes() == (tmp_path / "one" / name).read_bytes(), name
    with pytest.raises(ValueError, match="more than once"):
        run_bench(cfg(tmp_path / "three", "[semantic,gt]"), [parts[0], parts[0]])


def test_a_lane_count_other_than_1_or_2_exits_2_naming_it_without_output(tmp_path, capsys):
    from sdn3d.cli.demo import main

    assert main([f"output_dir={tmp_path / 'demo'}", "lanes=3"]) == 2
    assert "lanes must be 1" in capsys.readouterr().err
    assert not (tmp_path / "demo").exists()


@pytest.mark.parametrize("sources", [BOTH, [Proposals.GT]])
def test_the_proposal_recall_runs_after_the_example_edits_beside_the_predicted_row(tmp_path, monkeypatch, sources):
    """With a predicted row, its lane runs the benchmark alone and the edits' lane the proposal recall after the
    edits (each step's results are the same in either task); without one, no recall runs."""
    from sdn3d.cli import demo
    from sdn3d.cli._config import compose_config

    specs = {}

    def command(spec, work, name):
        specs[name] = spec
        return [sys.executable, "-c", "pass"]

    monkeypatch.setattr(demo, "_lane_task_command", command)
    cfg = compose_config([f"output_dir={tmp_path / 'out'}", f"data_dir={tmp_path / 'data'}"], "demo")
    plan = demo.lane_plan(["semantic", "geometric", "textural"], False, sources, 2, 7)
    tasks = demo.lane_tasks(plan, cfg, tmp_path / "data", tmp_path / "out")
    for task in (t for lane in tasks for t in lane if not t.name.startswith("training")):
        task.start({}).wait()
    if Proposals.SEMANTIC in sources:
        assert specs["bench_predicted"]["steps"] == ["bench"]
        assert specs["edits"]["steps"] == ["edits", "recall"]
    else:
        assert "bench_predicted" not in specs and specs["edits"]["steps"] == ["edits"]
    assert specs["bench_oracle"]["steps"] == ["bench"]


def test_each_lane_task_starts_with_the_threads_its_plan_fixed_whatever_has_finished(tmp_path, monkeypatch):
    """The demo's semantic training child starts with 1 torch thread (``threads=1``, ``OMP_NUM_THREADS=1``) and
    ``threads_later={after_epochs:7,threads:2}``, every other child with 1, the same whether it starts first or
    after every other task ended (no thread count read off the other lane's state)."""
    from sdn3d.cli import demo
    from sdn3d.cli._config import compose_config

    seen: dict[str, list] = {}
    env_probe = [sys.executable, "-c", "import os; print(os.environ['OMP_NUM_THREADS'])"]
    real_command = demo._train_command

    def train_command(branch, cfg, data_root, runs, upstream=None, to_file=False, later=None):
        command = real_command(branch, cfg, data_root, runs, upstream, to_file, later)
        seen.setdefault(f"training: {branch}", []).append([a for a in command if a.startswith("threads")])
        return env_probe

    def task_command(spec, work, name):
        seen.setdefault(name, []).append([f"threads={spec['config']['threads']}"])
        return env_probe

    monkeypatch.setattr(demo, "_train_command", train_command)
    monkeypatch.setattr(demo, "_lane_task_command", task_command)
    monkeypatch.setattr(demo, "_finish", lambda branch, run_dir, code, started, new_run=None: {"best_ckpt": "x"})
    cfg = compose_config([f"output_dir={tmp_path / 'out'}", f"data_dir={tmp_path / 'data'}"], "demo")
    plan = demo.lane_plan(["semantic", "geometric", "textural"], False, BOTH, cfg.threads,
                          cfg.semantic_threads_after_epochs)
    tasks = [t for lane in demo.lane_tasks(plan, cfg, tmp_path / "data", tmp_path / "out") for t in lane]
    everything = {t.name: {"best_ckpt": "x", "bench": None, "edits": None} for t in tasks}
    for done in ({}, everything):  # started first, or last
        for task in tasks:
            assert task.start(done).wait() == 0
            seen.setdefault(f"OMP {task.name}", []).append(int(task.log.read_text()))
    slugs = {"benchmark: predicted row": "bench_predicted", "benchmark: oracle row": "bench_oracle",
             demo.EDITS_TASK: "edits", "training: geometric": "training: geometric",
             "training: textural": "training: textural"}
    assert seen == {"training: semantic": [["threads=1", "threads_later={after_epochs:7,threads:2}"]] * 2,
                    **{slugs[t.name]: [["threads=1"]] * 2 for t in tasks if t.name != "training: semantic"},
                    **{f"OMP {t.name}": [1, 1] for t in tasks}}


def test_the_report_gives_each_lane_task_its_threads():
    """The time table and the machine sentence say each task's threads as the plan fixed them (before: "2 lanes of 1
    torch thread each", also for a semantic training that took a second thread)."""
    from sdn3d.cli.demo import machine_sentence, stage_rows, threads_sentence

    threads = {"training: semantic": {"threads": 1, "after_epochs": 7, "then": 2},
               "training: geometric": {"threads": 1}}
    timeline = [{"lane": 1, "task": "training: semantic", "start_s": 31.0, "end_s": 500.0, "wall_s": 469.0,
                 "cpu_s": 600.0, "threads": threads["training: semantic"]},
                {"lane": 2, "task": "training: geometric", "start_s": 31.0, "end_s": 90.0, "wall_s": 59.0,
                 "cpu_s": 57.0, "threads": threads["training: geometric"]}]
    info = {"stages_s": {"data": 31.0, "train": 469.0, "after_training": 46.0}, "wall_s": 546.0,
            "lanes": {"lanes": 2, "threads": threads, "timeline": timeline},
            "machine": {"processor": "Test CPU", "logical_cpus": 2, "load_average_start": [0.5, 0, 0]}}
    rows = stage_rows(info)
    assert ("| lane 1: training: semantic, 1 torch thread for its first 7 epochs, then 2 (from 31 s to 500 s; CPU "
            "600 s) | 469 |") in rows
    assert "| lane 2: training: geometric, 1 torch thread (from 31 s to 90 s; CPU 57 s) | 59 |" in rows
    assert ("Test CPU, 2 logical cores, 2 lanes (training: semantic 1 torch thread for its first 7 epochs, then 2; "
            "every other stage 1 torch thread)") in machine_sentence(info)
    assert threads_sentence({"a": {"threads": 1}, "b": {"threads": 1}}) == "1 torch thread each"
    assert threads_sentence({"a": {"threads": 2}, "b": {"threads": 1}, "c": {"threads": 2}}) == \
        "b 1 torch thread; every other stage 2 torch threads"
