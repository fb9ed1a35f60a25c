"""sdn3d-synth under faults (issue 20): a SIGKILLed run leaves no worker process behind and the next run
removes its staging tree; staging trees of live runs, other hosts and other tools are left alone; the
working directory is never replaced. Linux only (the helpers read /proc)."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from faults.processes import (
    group_members,
    proc_info,
    process_group,
    sigkill_leader,
    survivors,
    wait_for_files,
    wait_until_gone,
)

from sdn3d.data.synth import MANIFEST_NAME, SynthConfig, generate_dataset
from sdn3d.io import OWNER_FILE, owner_record, remove_stale_staging

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").is_file(), reason="needs Linux /proc")

SMALL = dict(frames_per_sequence=1, edit_pairs=0, image_size=(64, 24), worlds=("0001",), variations=("clone",))


def _dead_pid() -> int:
    """The pid of a process that has just ended (and been reaped)."""
    proc = subprocess.Popen(["true"])
    proc.wait()
    return proc.pid


def _tree(parent: Path, name: str, owner: dict | None, content: str = "x") -> Path:
    tree = parent / name
    (tree / "sub").mkdir(parents=True)
    (tree / "sub" / "f.txt").write_text(content)
    if owner is not None:
        (tree / OWNER_FILE).write_text(json.dumps(owner))
    return tree


def test_killed_run_leaves_no_worker_and_the_next_run_removes_its_tree(tmp_path: Path) -> None:
    """SIGKILL the parent of a 2-worker run mid-way: its workers die with it (they used to keep rendering
    into a ``.partial-*`` tree at full CPU), and the next run into the same output_dir removes that tree."""
    out = tmp_path / "data"
    cmd = [sys.executable, "-m", "sdn3d.cli.synth", f"output_dir={out}", "workers=2", "threads=1",
           "worlds=[0001,0002]", "variations=[clone]", "frames_per_sequence=400", "edit_pairs=0",
           "image_size=[160,64]", f"hydra.run.dir={tmp_path / 'hydra'}"]
    with process_group(cmd, log=tmp_path / "synth.log") as proc:
        # Both workers are rendering once each world has a frame in the staging tree.
        for world in ("0001", "0002"):
            wait_for_files(tmp_path, f".data.partial-*/vkitti_1.3.1_rgb/{world}/clone/*.png", timeout=90, proc=proc)
        workers = group_members(proc.pid, exclude_leader=True)
        assert len(workers) >= 2, (workers, (tmp_path / "synth.log").read_text())
        (partial,) = tmp_path.glob(".data.partial-*")
        assert json.loads((partial / OWNER_FILE).read_text())["pid"] == proc.pid
        sigkill_leader(proc)
        left = wait_until_gone(workers, timeout=5)
        assert not left, f"workers still running 5 s after their parent was killed: {left}"
        assert not survivors(group_members(proc.pid)), "a process of the killed run is still running"
        frames = sorted(partial.rglob("*.png"))
        time.sleep(0.3)
        assert sorted(partial.rglob("*.png")) == frames  # nothing writes into it any more
    assert not out.exists() and partial.is_dir()  # what the killed run left: its staging tree only

    generate_dataset(SynthConfig(output_dir=str(out), **SMALL))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data", "hydra", "synth.log"]
    assert (out / "_SUCCESS").is_file() and not (out / OWNER_FILE).exists()


def test_stale_trees_of_ended_runs_only_are_removed(tmp_path: Path) -> None:
    host = socket.gethostname()
    dead = {"pid": _dead_pid(), "host": host, "start": None}
    me = owner_record()
    assert me["pid"] == os.getpid() and me["host"] == host and me["start"] == proc_info(os.getpid()).start
    reused = dict(me, start=me["start"] + 1)  # our pid, but recorded for an earlier process: that one ended
    out = tmp_path / "data"
    out.mkdir()
    (out / "keep.txt").write_text("current dataset")
    stale = [
        _tree(tmp_path, ".data.partial-dead", dead),
        _tree(tmp_path, ".data.partial-reused", reused),
        _tree(tmp_path, ".data.old-dead", dead),  # the previous dataset being deleted when the run died
    ]
    kept = [
        _tree(tmp_path, ".data.partial-live", me),  # a run still writing
        _tree(tmp_path, ".data.partial-otherhost", dict(dead, host=host + "-elsewhere")),  # shared file system
        _tree(tmp_path, ".data.partial-norecord", None),  # another tool's staging (sdn3d-edit) or an older run
        _tree(tmp_path, ".data.partial-badrecord", None),
        _tree(tmp_path, ".other.partial-dead", dead),  # another output_dir's
        _tree(tmp_path, ".data.partialx-dead", dead),
    ]
    (kept[3] / OWNER_FILE).write_text("{not json")
    removed = remove_stale_staging(out)
    assert sorted(removed) == sorted(stale)
    assert not any(t.exists() for t in stale)
    assert all((t / "sub" / "f.txt").is_file() for t in kept)
    assert (out / "keep.txt").read_text() == "current dataset"


def test_run_killed_between_the_two_renames_gets_its_previous_dataset_back(tmp_path: Path) -> None:
    """Killed after the old dataset was moved aside and before the new one took its place: the old one is
    put back (not deleted), the unfinished new one removed, and the run goes on replacing it normally."""
    dead = {"pid": _dead_pid(), "host": socket.gethostname(), "start": None}
    out = tmp_path / "data"
    old = _tree(tmp_path, ".data.old-abc", dead)
    (old / "sub").rename(old / "tree")
    (old / "tree" / MANIFEST_NAME).write_text("{}")
    partial = _tree(tmp_path, ".data.partial-abc", dead)
    assert sorted(remove_stale_staging(out)) == sorted([old, partial])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data"]
    assert (out / "f.txt").read_text() == "x" and (out / MANIFEST_NAME).is_file()
    with pytest.raises(FileExistsError, match="overwrite=true"):
        generate_dataset(SynthConfig(output_dir=str(out), **SMALL))
    generate_dataset(SynthConfig(output_dir=str(out), overwrite=True, **SMALL))
    assert (out / "_SUCCESS").is_file() and not (out / "f.txt").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data"]


def test_worker_without_prctl_ends_with_its_owner(tmp_path: Path) -> None:
    """Where prctl is unavailable a worker polls for the process that generates the dataset and exits once
    it is gone."""
    owner = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    code = ("import time, sdn3d.data.synth.generate as g\n"
            "g._die_with_parent = lambda: False\n"
            f"g._init_worker({owner.pid})\n"
            "print('watching', flush=True)\n"
            "time.sleep(30)\n"
            "print('survived', flush=True)\n")
    worker = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert worker.stdout.readline().strip() == "watching"
        assert worker.poll() is None
        owner.kill()
        owner.wait()
        assert worker.wait(timeout=10) == 1
        assert "survived" not in worker.stdout.read()
    finally:
        owner.kill()
        worker.kill()
        owner.wait()
        worker.wait()


def test_cli_refuses_the_working_directory(tmp_path: Path) -> None:
    """Issue 20's probe: ``cd <dir> && sdn3d-synth output_dir=. overwrite=true`` deleted <dir>, exit 0."""
    work = tmp_path / "work"
    work.mkdir()
    (work / "notes.txt").write_text("mine")
    (work / MANIFEST_NAME).write_text("{}")  # even an earlier dataset: it is the working directory
    proc = subprocess.run(
        [sys.executable, "-m", "sdn3d.cli.synth", "output_dir=.", "overwrite=true", "frames_per_sequence=1",
         f"hydra.run.dir={tmp_path / 'hydra'}"], cwd=work, capture_output=True, text=True, timeout=120,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("sdn3d-synth: error: "), proc.stderr
    assert f"'{work}' is the current working directory" in lines[0]
    assert sorted(p.name for p in work.iterdir()) == sorted([MANIFEST_NAME, "notes.txt"])
    assert {p.name for p in tmp_path.iterdir()} <= {"hydra", "work"}  # no staging tree beside it either
