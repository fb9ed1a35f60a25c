"""EditSession (sdn3d.editing.session): the one code path of sdn3d-edit and sdn3d-app. An image is de-rendered once
per set of boxes, any spec is applied to that scene, and what the photo appearance keeps between edits
(its appearance's SourceState) leaves every picture bit-identical to a fresh call."""

from __future__ import annotations

import json

import numpy as np
import pytest
import torch
from helpers.tiny_models import write_checkpoints
from PIL import Image

import sdn3d.derender
from sdn3d.cli._config import compose_config
from sdn3d.cli.edit import load_models, main, open_input, resolve_checkpoints
from sdn3d.data import vkitti1
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.photo.transfer import PhotoSource, render_photo
from sdn3d.editing.session import EditSession
from sdn3d.editing.settings import session_settings
from sdn3d.editing.spec import EditError, parse_edit_spec

FRAME = "0001/clone/00004"


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


def _overrides(tiny_synth, ckpts):
    return ["data=synth", f"data.root={tiny_synth}", "data.image_size=[160,64]", f"input.frame={FRAME}",
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32", "geometric.min_pixels=1",
            "proposals=gt"]


@pytest.fixture(scope="module")
def opened(tiny_synth, ckpts):
    """``(cfg, EditInput, a session factory)`` of the tiny synthetic frame (ground-truth proposals: the random-weight
    semantic branch finds no car)."""
    cfg = compose_config(_overrides(tiny_synth, ckpts), "edit")
    inp, record = open_input(cfg)
    checkpoints = resolve_checkpoints(cfg, record)
    models, bank = load_models(cfg, checkpoints)
    return cfg, inp, lambda: EditSession(models, bank, session_settings(cfg, checkpoints))


def test_an_image_is_derendered_once_per_set_of_boxes(opened, monkeypatch):
    _, inp, make = opened
    calls = []
    real = sdn3d.derender.derender
    monkeypatch.setattr(sdn3d.derender, "derender", lambda *a, **k: calls.append(k.get("boxes")) or real(*a, **k))
    session = make()
    first = session.derender(inp)
    ids = first.scene.objects.instance_id.tolist()
    spec = parse_edit_spec([{"op": "delete", "id": ids[0]}])
    assert session.derender(inp, spec) is first and len(calls) == 1  # no boxes: the same scene
    # force: true: a box on this tiny synthetic frame is no car-sized object (the test is of the cache)
    boxed = parse_edit_spec({"objects": [{"box": [100, 10, 140, 40], "class": "Car", "force": True}], "ops": []})
    with_box = session.derender(inp, boxed)
    assert with_box is not first and len(calls) == 2 and len(calls[1]) == 1
    assert session.derender(inp, boxed) is with_box and len(calls) == 2
    session.forget(inp.key)
    session.derender(inp)
    assert len(calls) == 3


def test_edits_of_one_scene_are_bit_identical_to_fresh_sessions(opened):
    """The app edits one cached scene again and again (its SourceState kept between edits); each picture is the one a
    fresh session (sdn3d-edit's single call) draws."""
    _, inp, make = opened
    kept = make()
    scene = kept.derender(inp)
    table = scene.scene.objects
    ids = table.instance_id[table.has_geometry].tolist()
    specs = [[{"op": "rotate", "id": ids[0], "ry_deg": 40}],
             [{"op": "delete", "id": ids[1]}, {"op": "move", "id": ids[0], "to": [60, 50]}],
             [{"op": "rotate", "id": ids[0], "ry_deg": 40}],  # again: the cached hole and fill
             [{"op": "recolor", "id": ids[0], "color": "red"}]]
    for ops in specs:
        spec = parse_edit_spec(ops)
        again = kept.edit(scene, spec)
        fresh_session = make()
        fresh = fresh_session.edit(fresh_session.derender(inp), spec)
        assert again.edited.shape == (64, 160, 3)
        assert np.array_equal(again.edited, fresh.edited), ops
        assert torch.equal(again.source_map, fresh.source_map)
    assert (kept.edit(scene, parse_edit_spec(specs[0])).edited != inp.picture).any()  # something was drawn


def test_a_refused_spec_names_the_op_and_leaves_the_scene_as_it_was(opened):
    _, inp, make = opened
    session = make()
    scene = session.derender(inp)
    before = scene.scene.objects.location.clone()
    with pytest.raises(EditError, match=r"op 0 \(move id=12999\): no object with id 12999"):
        session.edit(scene, parse_edit_spec([{"op": "move", "id": 12999, "to": [10, 10]}]))
    assert torch.equal(scene.scene.objects.location, before)


def test_the_photo_cache_serves_one_scene_only(opened):
    _, inp, make = opened
    session = make()
    a = session.derender(inp)
    table = a.scene.objects
    iid = int(table.instance_id[table.has_geometry][0])
    edited = session.resolve(a, parse_edit_spec([{"op": "rotate", "id": iid, "ry_deg": 30}]))[1]
    cache = PhotoSource(inp.original, inp.frame, a.scene, settings=PhotoSettings())
    render_photo(inp.original, inp.frame, a.scene, edited, settings=PhotoSettings(), source=cache)
    other = a.scene.replace(objects=a.scene.objects)
    with pytest.raises(ValueError, match="one \\(original, scene, transform, settings\\)"):
        render_photo(inp.original, inp.frame, other, edited, settings=PhotoSettings(), source=cache)
    with pytest.raises(ValueError):
        render_photo(inp.original, inp.frame, a.scene, edited, settings=PhotoSettings(fill="telea"), source=cache)


def test_sdn3d_edit_and_the_session_draw_the_same_picture(opened, tiny_synth, ckpts, tmp_path):
    """The CLI is the session's single call: its edited.png is the session's picture, bit for bit."""
    _, inp, make = opened
    session = make()
    scene = session.derender(inp)
    iid = int(scene.scene.objects.instance_id[scene.scene.objects.has_geometry][0])
    ops = [{"op": "rotate", "id": iid, "ry_deg": -35}, {"op": "move", "id": iid, "to": [70, 52]}]
    (tmp_path / "ops.yaml").write_text("".join(f"- {json.dumps(op)}\n" for op in ops))
    out = tmp_path / "out"
    assert main([*_overrides(tiny_synth, ckpts), f"edits={tmp_path / 'ops.yaml'}", f"output_dir={out}"]) == 0
    written = np.asarray(Image.open(tmp_path / "out" / "edited.png"))
    assert np.array_equal(written, session.edit(scene, parse_edit_spec(ops)).edited)
    record = json.loads((tmp_path / "out" / "edit.json").read_text())
    assert record["input"] == vkitti1.read_frames(tiny_synth)[4].key and record["ops"][0]["op"] == "Rotate"


def test_the_session_reads_the_geometric_crops_from_the_input_photo(opened, monkeypatch):
    """sdn3d-edit and the browser editor (one EditSession) give derender the input at its own resolution."""
    _, inp, make = opened
    given = []
    real = sdn3d.derender.derender
    monkeypatch.setattr(sdn3d.derender, "derender", lambda *a, **k: given.append(k.get("photo")) or real(*a, **k))
    scene = make().derender(inp).scene
    photo = given[0]
    assert scene.meta["crops_from"] == "photo"
    assert tuple(photo.image.shape) == (3, inp.picture.shape[0], inp.picture.shape[1])
    torch.testing.assert_close(photo.image, torch.from_numpy(inp.picture).permute(2, 0, 1).float() / 255)
    assert photo.scale == inp.frame.scale and tuple(photo.offset) == tuple(inp.frame.offset)
