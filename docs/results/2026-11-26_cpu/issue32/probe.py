# ruff: noqa  (a throwaway probe script kept as the record of how PROBES.md was measured)
"""Issue 32 probes runnable without trained outputs; prints one line per probe: name | outcome."""
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import torch
from PIL import Image

tmp = Path(tempfile.mkdtemp(prefix="probe32_"))
W, H = 83, 25


def run(name, fn):
    try:
        out = fn()
    except BaseException as exc:  # noqa
        from sdn3d.errors import UserInputError
        kind = "clear error (UserInputError)" if isinstance(exc, UserInputError) else f"TRACEBACK {type(exc).__name__}"
        out = f"{kind}: {str(exc)[:110]!r} (len {len(str(exc))})"
    print(f"{name} | {out}", flush=True)


def cfg(*over):
    from sdn3d.cli._config import compose_config
    return compose_config(list(over), "edit")


def img16():
    im = Image.new("I;16", (W, H)); im.frombytes(np.full((H, W), 16384, "<u2").tobytes(), "raw", "I;16")
    im.save(tmp / "g16.png")
    from sdn3d.cli.edit import load_input
    image = load_input(cfg(f"input.image={tmp/'g16.png'}", "image_size=[83,25]"))[0]
    return f"read as mean {float(image.mean()):.3f} (true 0.25)"


def imgf():
    Image.fromarray(np.full((H, W), 0.5, np.float32)).save(tmp / "f.tif")
    from sdn3d.cli.edit import load_input
    image = load_input(cfg(f"input.image={tmp/'f.tif'}", "image_size=[83,25]"))[0]
    return f"read as mean {float(image.mean()):.3f} (true 0.5)"


def imghdr():
    Image.fromarray(np.full((H, W), 4.0, np.float32)).save(tmp / "hdr.tif")
    from sdn3d.cli.edit import load_input
    image = load_input(cfg(f"input.image={tmp/'hdr.tif'}", "image_size=[83,25]"))[0]
    return f"accepted silently, mean {float(image.mean()):.3f}"


def outdir_user_file():
    out = tmp / "out1"; out.mkdir()
    (out / "edited.png").write_bytes(b"x"); (out / "notes.txt").write_text("mine")
    (out / "edit.json").write_text(json.dumps({"outputs": ["edited.png", "edit.json"]}))
    from sdn3d.io import check_output_dir
    try:
        check_output_dir(out, "edit.json", True, listed_in="outputs")
    except TypeError:
        check_output_dir(out, "edit.json", True)
    return "accepted: output_dir (with notes.txt) would be replaced whole -> notes.txt deleted"


def input_inside():
    out = tmp / "out2"; out.mkdir()
    (out / "edited.png").write_bytes(b"x")
    (out / "edit.json").write_text(json.dumps({"outputs": ["edited.png", "edit.json"]}))
    from sdn3d.cli import edit
    c = cfg(f"input.image={out/'edited.png'}", f"output_dir={out}")
    from sdn3d.io import check_output_dir
    if hasattr(edit, "_output_rules"):
        check_output_dir(out, "edit.json", True, **edit._output_rules(c))
    else:
        check_output_dir(out, "edit.json", True)
    return "accepted: the input image inside output_dir would be deleted"


def ckpts():
    sys.path.insert(0, str(Path.cwd() / "tests"))
    from helpers.tiny_models import write_checkpoints
    return write_checkpoints(tmp / "ck")


def export_existing():
    from sdn3d.cli.export_weights import main
    c = ckpts(); o = tmp / "mine.pt"; o.write_text("user file")
    code = main([str(c["semantic"]), str(o)])
    return f"exit {code}; OUT {'kept' if o.read_text(errors='ignore') == 'user file' else 'OVERWRITTEN'}"


def export_training():
    from sdn3d.cli.export_weights import main
    c = ckpts(); t = torch.load(c["semantic"], weights_only=True)
    t |= {"pytorch-lightning_version": "2.4", "optimizer_states": []}
    torch.save(t, tmp / "last.ckpt"); before = (tmp / "last.ckpt").read_bytes()
    code = main([str(c["geometric"]), str(tmp / "last.ckpt"), *(["--overwrite"] if "--overwrite" in __import__("sdn3d.cli.export_weights", fromlist=["x"])._parser().format_help() else [])])
    return f"exit {code}; last.ckpt {'kept' if (tmp/'last.ckpt').read_bytes() == before else 'OVERWRITTEN by an export'} (with --overwrite where it exists)"


def alias_small():
    from sdn3d.editing.spec import load_edit_spec
    (tmp / "a.yaml").write_text("- &a {op: delete, id: 12001}\n- *a\n")
    return f"accepted ({len(load_edit_spec(tmp/'a.yaml'))} ops)"


def alias_moderate():
    levels = ['&a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for level in "bcde":  # 59049 strings: before, the message echoed them all (about 0.5 MB)
        levels.append(f"&{level} [" + ", ".join([f"*{chr(ord(level) - 1)}"] * 9) + "]")
    (tmp / 'b.yaml').write_text("- {op: rotate, id: 12001, ry_deg: [" + ", ".join(levels) + "]}\n")
    from sdn3d.editing.spec import load_edit_spec
    t = time.perf_counter()
    try:
        load_edit_spec(tmp / "b.yaml")
    except Exception as exc:
        return f"{type(exc).__name__}, message {len(str(exc))} chars, {time.perf_counter()-t:.2f} s"
    return "accepted"


def long_value():
    (tmp / "c.yaml").write_text("- {op: move, id: 12001, to: '" + "x" * 1_000_000 + "'}\n")
    from sdn3d.editing.spec import load_edit_spec
    try:
        load_edit_spec(tmp / "c.yaml")
    except Exception as exc:
        return f"{type(exc).__name__}, message {len(str(exc))} chars"


def huge_int():
    (tmp / "d.yaml").write_text("- {op: delete, id: " + "9" * 20000 + "}\n")
    from sdn3d.editing.spec import load_edit_spec
    load_edit_spec(tmp / "d.yaml")
    return "accepted"


def many_ops():
    from sdn3d.editing.spec import parse_edit_spec
    return f"accepted {len(parse_edit_spec([{'op': 'delete', 'id': 12001}] * 960))} ops"


def ry_deg():
    from sdn3d.editing.spec import parse_edit_spec
    return f"accepted, ry = {parse_edit_spec([{'op': 'rotate', 'id': 12001, 'ry_deg': '1e308'}]).ops[0].ry!r}"


def edit_setting(over):
    def f():
        import contextlib
        import io

        from sdn3d.cli.edit import main
        (tmp / "o.yaml").write_text("- {op: delete, id: 12001}\n")
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            try:
                code = main([f"edits={tmp/'o.yaml'}", f"output_dir={tmp/'os'}", over, "input.image=/nonexistent.png"])
            except BaseException as exc:
                return f"TRACEBACK {type(exc).__name__}: {str(exc)[:80]}"
        return f"exit {code}: {err.getvalue().strip()[:120]}"
    return f


def proc_dir():
    from sdn3d.cli.edit import _read_inputs
    (tmp / "p.yaml").write_text("- {op: delete, id: 12001}\n")
    Image.fromarray(np.zeros((375, 1242, 3), np.uint8)).save(tmp / "v.png")
    _read_inputs(cfg(f"edits={tmp/'p.yaml'}", "output_dir=/proc/sdn3d-probe/out", f"input.image={tmp/'v.png'}"))
    return "inputs accepted: fails only when writing, after de-rendering"


def duplicates():
    from sdn3d.editing.apply import Duplicate
    from sdn3d.math3d.camera import Intrinsics
    from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject
    h, w = 192, 624
    car = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), location=(0.0, 1.6, 12.0))
    scene = SceneCode(Intrinsics(725.0 / 2, 725.0 / 2, 311.5, 93.5, width=w, height=h), torch.zeros(h, w, dtype=torch.long),
                      "vkitti", ObjectTable.from_objects([car], h, w), background_codes={})
    ops = [Duplicate(12001, (10.0 + 0.6 * k, 180.0)) for k in range(900)]
    t = time.perf_counter(); from sdn3d.editing import apply as A
    table, codes = scene.objects, scene.background_codes
    if hasattr(A, "_Copies"):
        copies = A._Copies()
        for op in ops:
            table, codes = A._apply_one(scene, table, codes, op, copies)
        table = copies.into(table)
    else:
        for op in ops:
            table, codes = A._apply_one(scene, table, codes, op)
    return f"900 duplicate ops applied to the table in {time.perf_counter()-t:.2f} s ({len(table)} rows)"


def partial_left():
    from sdn3d.io import OWNER_FILE, owner_record
    child = subprocess.Popen([sys.executable, "-c", "pass"]); child.wait()
    tree = tmp / ".res.partial-killed"; tree.mkdir()
    (tree / OWNER_FILE).write_text(json.dumps(owner_record() | {"pid": child.pid, "start": None}))
    import inspect

    from sdn3d.cli import edit
    owned = "owned=True" in inspect.getsource(edit._write_outputs)
    return f"edit stages with owned={owned}: a killed edit's .partial-* tree is {'removed by the next run' if owned else 'left forever'}"


def two_edits():
    from sdn3d import io
    return "second writer refused (io.writer_lock)" if hasattr(io, "writer_lock") else "no lock: both runs write, both exit 0, one result lost"


for name, fn in [("16-bit grey PNG input", img16), ("float32 TIFF input", imgf), ("float TIFF with values 4.0", imghdr),
                 ("output_dir holding edit.json + a user's file", outdir_user_file),
                 ("input.image inside output_dir", input_inside),
                 ("export-weights CKPT OUT, OUT a user's file", export_existing),
                 ("export-weights onto a training checkpoint", export_training),
                 ("YAML with an anchor and alias", alias_small), ("YAML alias expansion (9^5) in an error", alias_moderate),
                 ("1 MB value in an error message", long_value), ("20000-digit id", huge_int), ("960 ops", many_ops),
                 ("ry_deg: 1e308", ry_deg), ("threads=-3", edit_setting("threads=-3")), ("threads=0", edit_setting("threads=0")),
                 ("pick_radius=-1", edit_setting("pick_radius=-1")), ("pick_radius=nan", edit_setting("pick_radius=nan")),
                 ("output_dir under /proc", proc_dir), ("900 duplicate ops", duplicates),
                 (".partial-* of a killed edit", partial_left), ("two edits into one output_dir", two_edits)]:
    run(name, fn)
