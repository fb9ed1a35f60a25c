# ruff: noqa  (a throwaway probe script kept as the record of how PROBES.md rows 28-46 were measured)
"""Issue 32 probes of training runs (resume, relocation), run= and the CLIs' exit codes; one line per probe.

    PYTHONPATH=<tree>/src:<tree> python probe_runs.py     # in a worktree of the commit to measure

Trains a tiny semantic run (2 epochs of 1 batch, 160x64 synthetic data) once, then probes copies of it.
"""
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

tmp = Path(tempfile.mkdtemp(prefix="probe32r_"))
ENV = {**os.environ, "OMP_NUM_THREADS": "1"}


def sh(*args, cwd=tmp):
    proc = subprocess.run([sys.executable, "-m", *args], cwd=cwd, env=ENV, capture_output=True, text=True, timeout=600)
    lines = [l for l in proc.stderr.strip().splitlines() if l.strip()]
    tb = "Traceback" in proc.stderr or "Error executing job" in proc.stderr
    last = next((l for l in reversed(lines) if "HYDRA_FULL_ERROR" not in l), "")
    return proc.returncode, tb, last[:150]


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()[:10] if path.is_file() else "missing"


def train(*extra, cwd=tmp):
    return sh("sdn3d.cli.train", "branch=semantic", "experiment=demo", f"data.root={tmp / 'data'}",
              "data.image_size=[160,64]", f"summary_file={tmp / 'summary.jsonl'}", "trainer.limit_train_batches=1",
              "trainer.limit_val_batches=1", "trainer.limit_test_batches=1", "trainer.enable_progress_bar=false",
              "~callbacks.progress_bar", "datamodule.batch_size=2", *extra, cwd=cwd)


def resume(run, *extra):
    return sh("sdn3d.cli.train", f"resume={run}", *extra)


def line(name, text):
    print(f"{name} | {text}", flush=True)


from sdn3d.data.synth import SynthConfig, generate_dataset

generate_dataset(SynthConfig(output_dir=str(tmp / "data"), seed=0, image_size=(160, 64), frames_per_sequence=8,
                             cars_per_frame=(3, 5), edit_pairs=1, max_edit_operations=2))
base = tmp / "base"
code = train(f"hydra.run.dir={base}", "trainer.max_epochs=2")
assert code[0] == 0, code


def fresh(name):
    dst = tmp / name
    shutil.copytree(base, dst, symlinks=True)
    # the copy is the "same" run: its recorded paths are base's; rewrite them as sdn3d would have written them
    for f in (dst / "config.yaml", dst / "summary.json"):
        f.write_text(f.read_text().replace(str(base), str(dst)))
    return dst


# 28: smaller trainer.max_epochs than already trained
r = fresh("smaller"); before = digest(r / "summary.json")
c = resume(r, "trainer.max_epochs=1")
line("28 resume, trainer.max_epochs=1 < 2 trained", f"exit {c[0]}, traceback {c[1]}, summary.json "
     f"{'unchanged' if digest(r / 'summary.json') == before else 'REWRITTEN status ' + json.loads((r / 'summary.json').read_text())['status']}; {c[2]}")

# 29: last.ckpt is an export
r = fresh("export"); before = digest(r / "summary.json")
shutil.copy(r / "checkpoints" / "inference.pt", r / "checkpoints" / "last.ckpt")
c = resume(r, "trainer.max_epochs=3")
line("29 resume, last.ckpt an inference export", f"exit {c[0]}, traceback {c[1]}, summary.json "
     f"{'unchanged' if digest(r / 'summary.json') == before else 'REWRITTEN status ' + json.loads((r / 'summary.json').read_text())['status']}; {c[2]}")

# 30: ckpt_path= an export
c = train(f"hydra.run.dir={tmp / 'ckptpath'}", f"ckpt_path={base / 'checkpoints' / 'inference.pt'}", "trainer.max_epochs=3")
line("30 new run, ckpt_path=<inference.pt>", f"exit {c[0]}, traceback {c[1]}, run dir written: "
     f"{sorted(p.name for p in (tmp / 'ckptpath').iterdir()) if (tmp / 'ckptpath').exists() else []}; {c[2]}")

# 31: resume a finished run with the same budget
r = fresh("same"); before = digest(r / "summary.json"); ck = digest(r / "checkpoints" / "last.ckpt")
c = resume(r)
after = json.loads((r / "summary.json").read_text())
line("31 resume a finished run, same budget", f"exit {c[0]}, summary.json "
     f"{'unchanged' if digest(r / 'summary.json') == before else 'REWRITTEN (experiment ' + repr(after['experiment']) + ', overrides ' + repr(after['overrides']) + ')'}, "
     f"last.ckpt {'unchanged' if ck == digest(r / 'checkpoints' / 'last.ckpt') else 'changed'}; {c[2]}")

# 32: a copied run, original deleted, resumed for one more epoch
orig = tmp / "orig"; shutil.copytree(base, orig)
for f in (orig / "config.yaml", orig / "summary.json"):
    f.write_text(f.read_text().replace(str(base), str(orig)))
copy = tmp / "copy"; shutil.copytree(orig, copy); shutil.rmtree(orig)
c = resume(copy, "trainer.max_epochs=3")
s = json.loads((copy / "summary.json").read_text())
line("32 copy resumed, original deleted", f"exit {c[0]}, original dir recreated: {orig.exists()}"
     f"{' (' + ', '.join(sorted(p.name for p in orig.rglob('*') if p.is_file()))[:80] + ')' if orig.exists() else ''}; "
     f"copy's summary epoch {s['epoch']}, last_ckpt under copy: {str(s['last_ckpt']).startswith(str(copy))}, "
     f"best_ckpt under copy: {str(s['best_ckpt']).startswith(str(copy))}")

# 33: run= on a copy while the original exists
orig2 = tmp / "orig2"; shutil.copytree(base, orig2)
for f in (orig2 / "config.yaml", orig2 / "summary.json"):
    f.write_text(f.read_text().replace(str(base), str(orig2)))
copy2 = tmp / "runs_copy" / "semantic"; shutil.copytree(orig2, copy2)
from sdn3d.runs import find_run_checkpoints

chosen, _ = find_run_checkpoints(copy2.parent)
line("33 run= on a copied run, original present", f"loads {'the COPY' if chosen['semantic']['path'].startswith(str(copy2)) else 'the ORIGINAL'}'s "
     f"{Path(chosen['semantic']['path']).name}")

# 34: dotless overrides on resume
r = fresh("dotless"); side = tmp / "side.jsonl"
c = resume(r, "trainer.max_epochs=3", "torch_threads=1", f"summary_file={side}")
line("34 resume with torch_threads=1 summary_file=side.jsonl", f"exit {c[0]}, side.jsonl written: {side.is_file()}")

# 35: a typo among the resume overrides
r = fresh("typo"); before = digest(r / "summary.json")
c = resume(r, "trainer.max_epoch=3")
line("35 resume with trainer.max_epoch=3 (typo)", f"exit {c[0]}, traceback {c[1]}, summary.json "
     f"{'unchanged' if digest(r / 'summary.json') == before else 'REWRITTEN'}; {c[2]}")

# 36: a group choice on resume
r = fresh("group"); before = digest(r / "summary.json")
c = resume(r, "branch=geometric")
line("36 resume with branch=geometric", f"exit {c[0]}, summary.json "
     f"{'unchanged' if digest(r / 'summary.json') == before else 'REWRITTEN'}; {c[2]}")

# 46: a dotted override on resume that the saved (resolved) config copied elsewhere
r = fresh("dataroot"); before = digest(r / "summary.json")
c = resume(r, "trainer.max_epochs=3", f"data.root={tmp / 'no_such_data'}")
line("46 resume with data.root=<missing dir>", f"exit {c[0]}, summary.json "
     f"{'unchanged' if digest(r / 'summary.json') == before else 'REWRITTEN status ' + json.loads((r / 'summary.json').read_text())['status']}; {c[2]}")

# 37: run= when the newest summary is unreadable
runs = tmp / "runs2"
old = runs / "semantic" / "old"; shutil.copytree(base, old)
new = runs / "semantic" / "new"; shutil.copytree(base, new)
s = json.loads((old / "summary.json").read_text()); s["finished"] = "2020-01-01T00:00:00+00:00"
(old / "summary.json").write_text(json.dumps(s).replace(str(base), str(old)))
(new / "summary.json").write_text("{truncated")
try:
    chosen, _ = find_run_checkpoints(runs)
    line("37 run=, newest summary unreadable", f"silently uses the older run: {chosen['semantic']['summary'].startswith(str(old))}")
except Exception as exc:  # noqa
    line("37 run=, newest summary unreadable", f"{type(exc).__name__}: {str(exc)[:150]}")

# 38-39: sdn3d-bench with an empty / out-of-frame benchmark
sys.path.insert(0, str(Path(__file__).resolve().parents[4] / "tests"))
from helpers.tiny_models import write_checkpoints

ck = write_checkpoints(tmp / "ckpt")
(tmp / "empty.json").write_text("[]")
entries = json.loads((tmp / "data" / "vkitti_edit_benchmark.json").read_text())
for e in entries:
    for op in e["operations"]:
        op["from"] = {"u": 5000, "v": 5000}
        if op.get("to"):
            op["to"] = {"u": 6000, "v": 6000}
(tmp / "outside.json").write_text(json.dumps(entries))
for n, (name, bench) in enumerate((("empty entry list", "empty.json"), ("every point outside the frame", "outside.json"))):
    c = sh("sdn3d.cli.bench", f"data.root={tmp / 'data'}", "data.image_size=[160,64]", f"benchmark={tmp / bench}",
           f"checkpoints.geometric={ck['geometric']}", f"checkpoints.textural={ck['textural']}", "proposals=gt",
           "compose=photo", "geometric.crop_size=32", "geometric.min_pixels=1", f"output_dir={tmp / ('bench' + str(n))}")
    line(f"{38 + n} sdn3d-bench, {name}", f"exit {c[0]}, results written: {(tmp / ('bench' + str(n)) / 'results.json').is_file()}; {c[2]}")

# 40-44: Hydra override typos
for n, (tool, args) in enumerate((("train", ["trainer.max_epoch=3"]), ("train", ["trainer.max_epochs=[1"]),
                                  ("train", ["branch=semantik"]), ("synth", ["frames_per_sequenc=3"]),
                                  ("synth", ["seed=[1"]), ("render_demo", ["bogus_key=1"]))):
    c = sh(f"sdn3d.cli.{tool}", *args, f"hydra.run.dir={tmp / 'hydra' / str(n)}")
    line(f"{40 + n} sdn3d-{tool.replace('_', '-')} {' '.join(args)}", f"exit {c[0]}, traceback {c[1]}; {c[2]}")
print("tmp:", tmp)
