from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from sdn3d.io import atomic_write, write_json_atomic, write_png_atomic


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
