"""Texture-code tools: code maps, editing codes, the per-class code bank, the inference renderer."""

from __future__ import annotations

import pytest
import torch

from sdn3d.image_ops import boundary_map
from sdn3d.labels import class_list, region_class
from sdn3d.nets.pix2pixhd import TexturalSpec
from sdn3d.textural.codes import CodeBank, TextureCodes, code_donors, code_map, sample_code, set_code, swap_codes
from sdn3d.textural.renderer import TexturalRenderer

SPEC = dict(num_classes=14, ngf=8, n_downsampling=2, n_blocks=1, nef=4, n_downsampling_encoder=2, ndf=8)


def _scene(h: int = 16, w: int = 32) -> tuple[torch.Tensor, torch.Tensor]:
    """``(label, L)``: sky on top, road below, two cars in image 0, one in image 1."""
    L = torch.full((2, h, w), 5, dtype=torch.long)
    L[:, : h // 2] = 1
    L[0, h // 2:, :6] = 12001
    L[0, h // 2:, -6:] = 13002  # a van
    L[1, h // 2:, 10:16] = 12001
    label = region_class(L)
    return label, L


def _renderer() -> TexturalRenderer:
    torch.manual_seed(0)
    return TexturalRenderer(TexturalSpec(**SPEC))


def test_region_class_and_class_lists():
    assert region_class(torch.tensor([0, 5, 999, 12001, 13002])).tolist() == [0, 5, 999, 12, 13]
    assert len(class_list("vkitti")) == 14 and len(class_list("cityscapes")) == 19
    with pytest.raises(ValueError, match="classes"):
        class_list("kitti")


def test_boundary_map_marks_both_sides_of_every_4_neighbour_change():
    _, L = _scene()
    b = boundary_map(L)
    assert b.shape == (2, 1, 16, 32)
    for i in range(2):  # the definition written out pixel by pixel
        ref = torch.zeros(16, 32)
        for y in range(16):
            for x in range(32):
                neighbours = [(y + dy, x + dx) for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0))
                              if 0 <= y + dy < 16 and 0 <= x + dx < 32]
                ref[y, x] = float(any(L[i, yy, xx] != L[i, y, x] for yy, xx in neighbours))
        assert torch.equal(b[i, 0], ref)


def test_code_map_broadcasts_codes_and_handles_missing_regions():
    _, L = _scene()
    codes = TextureCodes(torch.tensor([0, 0, 0, 1, 1]), torch.tensor([1, 5, 12001, 1, 12001]),
                         torch.arange(10, dtype=torch.float32).view(5, 2))
    m = code_map(codes, L)
    assert m.shape == (2, 2, 16, 32)
    assert m[0, :, 0, 0].tolist() == [0, 1] and m[0, :, 15, 8].tolist() == [2, 3]
    assert m[0, :, 15, 0].tolist() == [4, 5] and m[1, :, 15, 12].tolist() == [8, 9]
    assert m[0, :, 15, 31].tolist() == [0, 0]  # image 0's van has no code: zeros
    assert m[1, :, 15, 0].tolist() == [0, 0]  # image 1's road has no code
    with pytest.raises(ValueError, match="no texture code for 2 region"):
        code_map(codes, L, missing="error")


def test_encode_then_code_map_equals_encoder_pooling():
    r = _renderer()
    _, L = _scene()
    image = torch.rand(2, 3, 16, 32)
    codes = r.encode(image, L)
    assert len(codes) == 7 and codes.code_dim == 5  # image 0: 1, 5, 12001, 13002; image 1: 1, 5, 12001
    assert torch.allclose(code_map(codes, L), r.encoder(image * 2 - 1, L), atol=1e-6)
    assert set(codes.image(1)) == {1, 5, 12001}
    assert torch.equal(codes.get(0, 13002), codes.image(0)[13002])
    with pytest.raises(KeyError):
        codes.get(1, 13002)


def test_set_swap_and_sample_codes():
    codes = TextureCodes(torch.tensor([0, 0, 1]), torch.tensor([5, 12001, 12001]),
                         torch.tensor([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))
    swapped = swap_codes(codes, (0, 12001), (1, 12001))
    assert swapped.get(0, 12001).tolist() == [2, 2] and swapped.get(1, 12001).tolist() == [1, 1]
    assert codes.get(0, 12001).tolist() == [1, 1]  # the input is not modified
    added = set_code(codes, 1, 5, torch.tensor([7.0, 7.0]))
    assert len(added) == 4 and added.get(1, 5).tolist() == [7, 7]
    with pytest.raises(ValueError, match="2 values"):
        set_code(codes, 0, 5, torch.zeros(3))

    bank = CodeBank.from_codes([codes, TextureCodes(torch.tensor([0]), torch.tensor([12007]),
                                                    torch.tensor([[5.0, 5.0]]))])
    assert bank.classes == [5, 12] and len(bank) == 4
    assert bank.codes[12].tolist() == [[1, 1], [2, 2], [5, 5]]
    assert bank.mean(12).tolist() == [pytest.approx(8 / 3)] * 2
    g = torch.Generator().manual_seed(0)
    draws = bank.sample(12, 50, generator=g)
    seen = {tuple(d.tolist()) for d in draws}
    assert seen <= {(1, 1), (2, 2), (5, 5)} and len(seen) > 1
    new = sample_code(codes, bank, 0, 12001, generator=torch.Generator().manual_seed(3))
    assert tuple(new.get(0, 12001).tolist()) in {(1, 1), (2, 2), (5, 5)}
    background = sample_code(codes, bank, 0, 5)  # a background class: region id = class id
    assert background.get(0, 5).tolist() == [0, 0]
    with pytest.raises(KeyError, match="class 1"):
        sample_code(codes, bank, 0, 1)
    assert CodeBank.from_codes([codes], objects_only=True).classes == [12]
    assert bank.colors is None and bank.code_dim == 2  # codes only: no colour to pick a code by


def test_code_bank_from_regions_groups_codes_and_colours_by_class():
    ids = torch.tensor([5, 12001, 13002, 12004, 5])
    codes = torch.arange(10.0).view(5, 2)
    colors = torch.arange(15.0).view(5, 3) / 15
    bank = CodeBank.from_regions(ids, codes, colors)
    assert bank.classes == [5, 12, 13] and len(bank) == 5
    assert bank.codes[12].tolist() == [[2, 3], [6, 7]] and torch.equal(bank.colors[12], colors[[1, 3]])
    assert torch.equal(bank.colors[5], colors[[0, 4]])


def test_code_donors_swap_objects_within_their_class_only():
    ids = torch.tensor([1, 12001, 12002, 5, 13001, 12003, 12004, 13002, 14001, 12005])
    for seed in range(20):
        donors = code_donors(ids, torch.Generator().manual_seed(seed))
        got = ids[donors]
        objects = ids >= 1000
        assert torch.equal(got[~objects], ids[~objects])  # background regions keep their code
        assert torch.equal(region_class(got), region_class(ids))  # a car gets a car's code, a van a van's
        assert torch.equal(torch.sort(donors[objects]).values, torch.nonzero(objects).view(-1))  # a permutation
        lonely = ids == 14001  # the only object of its class keeps its own
        assert bool((got[objects & ~lonely] != ids[objects & ~lonely]).all())
        assert bool((got[lonely] == ids[lonely]).all())
    assert len({tuple(code_donors(ids, torch.Generator().manual_seed(s)).tolist()) for s in range(20)}) > 1


def test_renderer_render_and_local_code_edit():
    r = _renderer()
    label, L = _scene(32, 64)
    image = torch.rand(2, 3, 32, 64)
    pose = torch.zeros(2, 24, 32, 64)
    normal = torch.zeros(2, 3, 32, 64)
    codes = r.encode(image, L)
    out = r.render(label, L, codes=codes, pose=pose, normal=normal)
    assert out.shape == (2, 3, 32, 64) and out.min() >= 0 and out.max() <= 1
    assert torch.allclose(out, r.reconstruct(image, label, L, pose=pose, normal=normal))
    assert torch.allclose(out, r.render(label, L, boundary_map(L), code_map=code_map(codes, L), pose=pose,
                                        normal=normal))
    # a new appearance for image 0's car changes the car more than the far side of the image (instance
    # norm spreads some change everywhere)
    edited = r.render(label, L, codes=set_code(codes, 0, 12001, torch.full((5,), 0.9)), pose=pose, normal=normal)
    change = (edited - out).abs().mean(1)
    car = L == 12001
    assert change[0][car[0]].mean() > 2 * change[0, 16:, 40:50].mean()
    assert torch.allclose(edited[1], out[1])  # other images untouched
    with pytest.raises(ValueError, match="codes or code_map"):
        r.render(label, L)
    with pytest.raises(ValueError, match="pose"):
        r.render(label, L, codes=codes, pose=torch.zeros(2, 12, 32, 64))


def test_renderer_from_state_dict_checks_inputs():
    r = _renderer()
    state = {f"generator.{k}": v for k, v in r.generator.state_dict().items()}
    state.update({f"encoder.{k}": v for k, v in r.encoder.state_dict().items()})
    state["discriminator.x"] = torch.zeros(1)  # other parts of the training module are ignored
    hparams = {**{k: v for k, v in SPEC.items() if k != "num_classes"}, "classes": "vkitti", "lr": 1e-3}
    again = TexturalRenderer.from_state_dict(state, hparams)
    label, L = _scene()
    image = torch.rand(2, 3, 16, 32)
    assert torch.allclose(again.reconstruct(image, label, L), r.reconstruct(image, label, L))
    with pytest.raises(ValueError, match="classes"):
        TexturalRenderer.from_state_dict(state, {"ngf": 8})
    del state["encoder.model.1.weight"]
    with pytest.raises(RuntimeError, match="model.1.weight"):
        TexturalRenderer.from_state_dict(state, hparams)
