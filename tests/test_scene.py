"""SceneCode: construction from ground truth, validation, lossless versioned storage."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
import torch

from sdn3d.data import cityscapes, vkitti1
from sdn3d.data.fixtures import write_vkitti1_fixture
from sdn3d.data.fixtures_cityscapes import write_cityscapes_fixture
from sdn3d.data.records import load_instances, load_semantic, mesh_name_for
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.image_ops import resize_map
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.math3d.camera import VKITTI_INTRINSICS
from sdn3d.math3d.transforms import bottom_to_center
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.scene.code import SCENE_FORMAT, SCENE_VERSION, ObjectTable, SceneCode, SceneFormatError, SceneObject
from sdn3d.scene.io import load_scene, save_scene

WORK = (160, 64)
CAR, VAN = VKITTI_CLASS_INDEX["Car"], VKITTI_CLASS_INDEX["Van"]


@pytest.fixture(scope="module")
def record(tmp_path_factory):
    root = tmp_path_factory.mktemp("vk1")
    write_vkitti1_fixture(root, frames=(0,), size=(310, 94))
    return vkitti1.read_frames(root)[0]


def _hand_scene(code_dim: int = 5) -> SceneCode:
    """Three objects: a car with FFD and codes, a van without a mask, a mask-only car."""
    intr = VKITTI_INTRINSICS.resized(64, 32)
    semantic = torch.full((32, 64), VKITTI_CLASS_INDEX["Road"], dtype=torch.long)
    semantic[:10] = VKITTI_CLASS_INDEX["Sky"]
    mask = torch.zeros(32, 64, dtype=torch.bool)
    mask[20:25, 5:9] = True
    gen = torch.Generator().manual_seed(1)
    objects = [
        SceneObject(CAR * 1000 + 1, 2, (4.1, 1.5, 1.8), 0.3, (1.0, 1.65, 12.0),
                    phi=0.01 * torch.randn(64, 3, generator=gen), code=torch.randn(code_dim, generator=gen),
                    mask=torch.zeros(32, 64, dtype=torch.bool)),
        SceneObject(VAN * 1000 + 4, 5, (4.9, 2.0, 1.95), -2.5, (-3.0, 1.65, 20.0), observed=False),
        SceneObject(CAR * 1000 + 7, -1, mask=mask, code=torch.ones(code_dim)),
    ]
    table = ObjectTable.from_objects(objects, 32, 64, code_dim)
    return SceneCode(intr, semantic, "vkitti", table, {VKITTI_CLASS_INDEX["Road"]: [0.5] * code_dim},
                     {"source": "hand", "note": 1.5})


def test_from_frame_takes_ground_truth(record):
    scene = scene_from_frame(record, image_size=WORK)
    instances = resize_map(torch.from_numpy(load_instances(record)), WORK)
    assert scene.image_size == WORK and scene.intrinsics == record.intrinsics.resized(*WORK)
    assert torch.equal(scene.semantic, resize_map(torch.from_numpy(load_semantic(record)), WORK))
    obj = scene.objects
    annotated = {o.track_id + 1: o for o in record.objects}
    assert sorted(obj.instance_id.tolist()) == sorted(int(i) for i in instances.unique() if i)
    for i, iid in enumerate(obj.instance_id.tolist()):
        ann = annotated[iid % 1000]
        assert TEMPLATE_NAMES[int(obj.template_id[i])] == mesh_name_for(ann)
        assert obj.dims[i].tolist() == list(ann.dims) and obj.location[i].tolist() == list(ann.location)
        assert float(obj.ry[i]) == ann.ry
        assert torch.equal(obj.mask[i], instances == iid) and bool(obj.observed[i])
    assert bool((obj.phi == 0).all()) and obj.code.shape == (len(obj), 5)
    assert torch.allclose(obj.center, bottom_to_center(obj.location, obj.dims[:, 1]))
    assert {int(c) for c in obj.class_id} <= {CAR, VAN} and scene.meta["source"] == record.key


def test_from_frame_cityscapes_gives_mask_only_objects(tmp_path):
    write_cityscapes_fixture(tmp_path, size=(128, 64))
    record = cityscapes.read_frames(tmp_path, "train")[0]
    scene = scene_from_frame(record)
    instances = torch.from_numpy(load_instances(record))
    assert scene.classes == "cityscapes" and len(scene.objects) == len(instances.unique()) - 1 > 0
    assert not bool(scene.objects.has_geometry.any()) and bool(scene.objects.has_mask.all())
    assert torch.equal(scene.objects.mask.any(0), instances != 0)


def test_save_load_round_trip_is_lossless(tmp_path):
    scene = _hand_scene()
    path = save_scene(scene, tmp_path / "out" / "scene")
    assert path.suffix == ".json" and path.with_suffix(".npz").is_file()
    head = json.loads(path.read_text())
    assert head["format"] == SCENE_FORMAT and head["version"] == SCENE_VERSION
    assert [o["template"] for o in head["objects"]] == ["wagon", "van", None]
    loaded = load_scene(path)
    assert loaded == scene
    assert loaded.objects.ry.dtype == torch.float64 and loaded.objects.phi.dtype == torch.float32
    assert float(loaded.objects.ry[0]) == 0.3 and loaded.meta == {"source": "hand", "note": 1.5}
    # The empty scene round-trips too, and a second save over the first replaces it.
    empty = scene.replace(objects=ObjectTable.empty(32, 64))
    assert load_scene(save_scene(empty, path)) == empty


def test_from_frame_scene_round_trips(record, tmp_path):
    scene = scene_from_frame(record, image_size=WORK)
    assert load_scene(save_scene(scene, tmp_path / "gt.json")) == scene


def _edit_header(path, change) -> None:
    head = json.loads(path.read_text())
    change(head)
    path.write_text(json.dumps(head))


@pytest.mark.parametrize(
    ("change", "field"),
    [
        (lambda h: h.update(version=2), "version"),
        (lambda h: h.update(format="other"), "format"),
        (lambda h: h["objects"][1].pop("dims"), "objects[1].dims"),
        (lambda h: h["objects"][0].update(ry="0.3"), "objects[0].ry"),
        (lambda h: h.update(image_size=[10, 10]), "image_size"),
        (lambda h: h["arrays"].update(sha256="0" * 64), "arrays.sha256"),
        (lambda h: h["arrays"].update(file="nothere.npz"), "arrays.file"),
    ],
)
def test_load_rejects_bad_files_naming_file_and_field(tmp_path, change, field):
    path = save_scene(_hand_scene(), tmp_path / "scene")
    _edit_header(path, change)
    with pytest.raises(SceneFormatError, match=rf"{re.escape(str(path))}.*field '{re.escape(field)}'"):
        load_scene(path)


def test_load_rejects_missing_and_corrupt_files(tmp_path):
    with pytest.raises(SceneFormatError, match="not found"):
        load_scene(tmp_path / "absent.json")
    (tmp_path / "junk.json").write_text("{not json")
    with pytest.raises(SceneFormatError, match="junk.json"):
        load_scene(tmp_path / "junk.json")
    path = save_scene(_hand_scene(), tmp_path / "scene")
    path.with_suffix(".npz").write_bytes(b"garbage")
    with pytest.raises(SceneFormatError, match="sha256"):
        load_scene(path)


def test_validation_errors_name_the_problem():
    scene = _hand_scene()
    obj = scene.objects
    with pytest.raises(ValueError, match="unique"):
        obj.replace(instance_id=torch.tensor([12001, 12001, 12007]))
    with pytest.raises(ValueError, match="neither geometry"):
        obj.replace(has_mask=torch.tensor([True, False, False]))
    with pytest.raises(ValueError, match="classes without instances"):
        scene.replace(objects=obj.replace(instance_id=torch.tensor([5001, 13004, 12007])))
    with pytest.raises(ValueError, match="semantic must be"):
        scene.replace(semantic=scene.semantic[:-1])
    with pytest.raises(ValueError, match="background_codes"):
        scene.replace(background_codes=torch.zeros(3, 5))
    with pytest.raises(ValueError, match="dims"):
        obj.replace(dims=obj.dims * torch.tensor([[1.0, -1.0, 1.0]]))
    with pytest.raises(TypeError):
        scene.replace(meta={"bad": object()})
    with pytest.raises(ValueError, match="classes"):
        scene.replace(classes="kitti")


def test_tables_are_batched_and_addressable():
    scene = _hand_scene()
    obj = scene.objects
    assert len(obj) == 3 and obj.has_geometry.tolist() == [True, True, False]
    assert obj.index_of(13004) == 1 and obj.object(1).class_id == VAN
    assert torch.equal(scene.background_codes[VKITTI_CLASS_INDEX["Road"]], torch.full((5,), 0.5))
    assert scene.background_codes[VKITTI_CLASS_INDEX["Sky"]].abs().sum() == 0
    rebuilt = ObjectTable.from_objects([obj.object(i) for i in range(3)], 32, 64)
    assert rebuilt == obj
    assert obj.select(torch.tensor([2, 0])).instance_id.tolist() == [12007, 12001]
    assert math.isclose(float(obj.center[1, 1]), 1.65 - 1.0)
    with pytest.raises(KeyError):
        obj.index_of(99001)
    assert scene.thing_classes.tolist() == [CAR, VAN] and np.array_equal(scene.image_size, (64, 32))
