from __future__ import annotations

import errno
import os

import numpy as np
import pytest
from PIL import Image

from sdn3d.io import DiskFullError, atomic_write, staged_directory, write_json_atomic, write_png_atomic


def test_atomic_write_keeps_old_content_when_writer_fails(tmp_path):
    target = tmp_path / "out.json"
    write_json_atomic(target, {"good": 1})

    def broken(handle):
        handle.write(b"{half")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError, match="disk full"):
        atomic_write(target, broken)
    assert target.read_text().strip().startswith('{\n  "good": 1')
    # no temporary files left behind
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.json"]


def test_png_roundtrip_uint8_and_uint16_deterministic(tmp_path):
    rgb = (np.arange(32 * 16 * 3) % 251).astype(np.uint8).reshape(16, 32, 3)
    depth = (np.arange(32 * 16) * 97).astype(np.uint16).reshape(16, 32)
    write_png_atomic(tmp_path / "a.png", rgb)
    write_png_atomic(tmp_path / "b.png", rgb)
    write_png_atomic(tmp_path / "d.png", depth)
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()
    np.testing.assert_array_equal(np.array(Image.open(tmp_path / "a.png")), rgb)
    np.testing.assert_array_equal(np.array(Image.open(tmp_path / "d.png")), depth)
    with pytest.raises(ValueError, match="float32"):
        write_png_atomic(tmp_path / "f.png", np.zeros((4, 4), np.float32))


def test_bad_checkpoints_are_clear_errors_naming_the_file(tmp_path):
    import pickle

    import pytest
    import torch

    from sdn3d.geometric.predict import GeometricPredictor
    from sdn3d.io import load_lightning_checkpoint
    from sdn3d.semantic.predict import SemanticPredictor
    from sdn3d.textural.renderer import TexturalRenderer

    garbage = tmp_path / "garbage.ckpt"
    garbage.write_bytes(b"not a checkpoint at all")
    truncated = tmp_path / "truncated.ckpt"
    torch.save({"state_dict": {"w": torch.zeros(1000)}}, truncated)
    truncated.write_bytes(truncated.read_bytes()[:200])
    code = tmp_path / "code.ckpt"  # an object weights_only refuses to build
    code.write_bytes(pickle.dumps({"state_dict": {}, "x": pickle.UnpicklingError("boom")}))
    not_lightning = tmp_path / "plain.ckpt"
    torch.save({"weights": torch.zeros(2)}, not_lightning)
    for loader in (GeometricPredictor.from_checkpoint, SemanticPredictor.from_checkpoint,
                   TexturalRenderer.from_checkpoint, load_lightning_checkpoint):
        for path in (garbage, truncated, code, not_lightning, tmp_path / "missing.ckpt"):
            with pytest.raises(ValueError, match=path.name):
                loader(path)


@pytest.mark.parametrize("zip_format", [True, False], ids=["zip", "old_format"])
def test_mmap_maps_torch_zip_files_and_reads_old_format_files_whole(tmp_path, monkeypatch, zip_format):
    """``load_torch_file(mmap=True)`` maps a file of torch's zip format; a file of the older format (which torch can
    not map) is read whole, the same content, instead of being refused as a bad file."""
    import torch

    from sdn3d.io import load_torch_file

    path = tmp_path / "weights.pt"
    torch.save({"w": torch.arange(6.0), "n": 3}, path, _use_new_zipfile_serialization=zip_format)
    calls = []
    real_load = torch.load
    monkeypatch.setattr(torch, "load", lambda *a, **k: calls.append(k["mmap"]) or real_load(*a, **k))
    content = load_torch_file(path, mmap=True)
    assert torch.equal(content["w"], torch.arange(6.0)) and content["n"] == 3
    assert calls == [zip_format]
    garbage = tmp_path / "garbage.pt"
    garbage.write_bytes(b"PK\x03\x04 but no zip archive")
    with pytest.raises(ValueError, match="garbage.pt"):
        load_torch_file(garbage, mmap=True)


def test_image_readers_refuse_decompression_bombs_before_decoding(tmp_path):
    """Issue 20: a small PNG declaring a huge image (Pillow: DecompressionBombError over ~179 MP, only a
    warning and a full decode between ~89 MP and that) is a clear error naming the file, limit 100 MP."""
    import warnings

    from faults.images import blank_png, declared_size_png

    from sdn3d.data.errors import DataFormatError
    from sdn3d.data.imageio import MAX_IMAGE_PIXELS, image_size, open_image, read_rgb

    assert MAX_IMAGE_PIXELS == 100_000_000
    bombs = {declared_size_png(tmp_path / "declared_400mp.png", 20000, 20000): "400 MP",
             declared_size_png(tmp_path / "declared_105mp.png", 10500, 10000): "10500x10000 = 105 MP",
             blank_png(tmp_path / "blank_105mp.png", 10500, 10000): "10500x10000 = 105 MP"}
    for path, size in bombs.items():
        for reader in (open_image, read_rgb, image_size):
            with pytest.raises(DataFormatError, match="image too large") as info:
                reader(path)
            assert str(info.value).startswith(f"{path}: ") and size in str(info.value)
            assert "100 MP limit" in str(info.value)
    under = blank_png(tmp_path / "blank_90mp.png", 10000, 9000)  # over Pillow's warning threshold, under ours
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert image_size(under) == (10000, 9000)


@pytest.mark.parametrize("umask", [0o022, 0o077, 0o002])
def test_outputs_follow_the_users_umask(tmp_path, umask):
    """Files and staged directories get what a plain open() / mkdir() would give them (mkstemp / mkdtemp
    alone make every output 0600 / 0700 whatever the umask)."""
    import stat

    from sdn3d.io import current_umask, staged_directory, write_text_atomic

    old = os.umask(umask)
    try:
        assert current_umask() == umask
        path = write_text_atomic(tmp_path / "a.txt", "x")
        with staged_directory(tmp_path / "out", "DONE") as tmp:
            write_text_atomic(tmp / "DONE", "")
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask
    assert stat.S_IMODE((tmp_path / "out").stat().st_mode) == 0o777 & ~umask
    assert stat.S_IMODE((tmp_path / "out" / "DONE").stat().st_mode) == 0o666 & ~umask


def _full(handle):
    handle.write(b"{half")
    raise OSError(errno.ENOSPC, "No space left on device")


def test_a_full_disk_is_named_and_leaves_nothing_half_written(tmp_path):
    """Issue 42 (8): a full disk raised a bare OSError [Errno 28] (a traceback in sdn3d-edit, 500 in the editor);
    now DiskFullError (still an OSError, errno kept) says so, naming the file or the output directory."""
    target = tmp_path / "out.json"
    with pytest.raises(DiskFullError) as caught:
        atomic_write(target, _full)
    assert caught.value.errno == errno.ENOSPC
    assert str(caught.value) == (f"the disk is full: could not write {str(target)!r} (No space left on device); "
                                 "nothing half-written is left; free some space and try again")
    assert not list(tmp_path.iterdir())
    out = tmp_path / "result"
    with staged_directory(out, "done.json") as tmp:
        write_json_atomic(tmp / "done.json", {"run": 1})
    pattern = (r"^the disk is full: could not write output_dir '.*result' \(maps/a.json\); nothing half-written is "
               "left and an earlier output there is unchanged")
    with pytest.raises(DiskFullError, match=pattern):
        with staged_directory(out, "done.json", overwrite=True) as tmp:
            atomic_write(tmp / "maps" / "a.json", _full)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result"]
    assert sorted(p.name for p in out.iterdir()) == ["done.json"]


_CHILD = """
import os, signal, sys, time
from pathlib import Path
import sdn3d.io as sio
from sdn3d.io import staged_directory, write_json_atomic

out, when = Path(sys.argv[1]), sys.argv[2]
if when == "swap":  # SIGTERM right after the earlier output was moved aside, before the new one is renamed in
    real = os.rename
    def rename(src, dst):
        real(src, dst)
        if Path(dst).name == "tree":
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.5)
    sio.os.rename = rename
with staged_directory(out, "done.json", overwrite=True, owned=True) as tmp:
    write_json_atomic(tmp / "done.json", {"run": 2})
    if when == "writing":
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(5)
"""


@pytest.mark.parametrize("when", ["writing", "swap"])
def test_a_sigterm_while_an_output_is_written_or_swapped_leaves_a_whole_output(tmp_path, when):
    """Issue 42 (9): a SIGTERM while a staged output was written left its .partial-* directory, and one between the
    two renames of the swap left no output at all. Now the first removes the staged tree (exit 143, the earlier
    output unchanged) and the second is held until the swap is done (the new output in place)."""
    import json
    import subprocess
    import sys

    out = tmp_path / "out"
    with staged_directory(out, "done.json") as tmp:
        write_json_atomic(tmp / "done.json", {"run": 1})
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    proc = subprocess.run([sys.executable, "-c", _CHILD, str(out), when], env=env, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode in (143, -15), proc.stderr
    assert json.loads((out / "done.json").read_text()) == {"run": 1 if when == "writing" else 2}
    assert sorted(p.name for p in out.iterdir()) == ["done.json"]
    leftovers = sorted(p.name for p in tmp_path.iterdir() if p.name != "out")
    assert leftovers == [] if when == "writing" else all(".out.old-" in n for n in leftovers), leftovers
