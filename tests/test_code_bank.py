"""The code bank file (codes of training regions + their mean colours), named colours, CIE Lab."""

from __future__ import annotations

import json

import pytest
import torch

from sdn3d.errors import UserInputError
from sdn3d.nets.pix2pixhd import TextureEncoder
from sdn3d.textural.code_bank import (
    NAMED_COLORS,
    CodeBankFileError,
    build_code_bank,
    code_bank_path,
    load_code_bank,
    named_color,
    save_code_bank,
)
from sdn3d.textural.codes import CodeBank, rgb_to_lab


def test_rgb_to_lab_reference_values():
    lab = rgb_to_lab(torch.tensor([[1.0, 1.0, 1.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0],
                                   [0.5, 0.5, 0.5]]))
    expected = torch.tensor([[100.0, 0.0, 0.0], [0.0, 0.0, 0.0], [53.24, 80.09, 67.20], [32.30, 79.19, -107.86],
                             [53.39, 0.0, 0.0]])  # standard sRGB (D65) -> Lab values
    torch.testing.assert_close(lab, expected, atol=0.02, rtol=0)


def test_named_colors_are_forgiving_about_spelling_and_refuse_unknown_names():
    assert named_color("Red") == NAMED_COLORS["red"]
    assert named_color("dark_blue") == named_color("Dark-Blue") == named_color("darkblue") == NAMED_COLORS["dark blue"]
    assert named_color("gray") == NAMED_COLORS["grey"]
    with pytest.raises(UserInputError, match=r"op 3: unknown colour 'chartreuse'; known colours: red, orange"):
        named_color("chartreuse", "op 3")


def _bank() -> CodeBank:
    codes = {12: torch.tensor([[0.0, 1.0], [2.0, 3.0], [4.0, 5.0]]), 1: torch.tensor([[9.0, 9.0]])}
    colors = {12: torch.tensor([[0.7, 0.1, 0.1], [0.1, 0.2, 0.7], [0.9, 0.9, 0.9]]), 1: torch.tensor([[0.4, 0.6, 0.9]])}
    return CodeBank(codes, colors)


def test_nearest_picks_the_code_of_the_lab_nearest_colour():
    bank = _bank()
    code, color = bank.nearest(12, torch.tensor(named_color("red")))
    assert code.tolist() == [0, 1] and color.tolist() == pytest.approx([0.7, 0.1, 0.1])
    assert bank.nearest(12, torch.tensor(named_color("blue")))[0].tolist() == [2, 3]
    assert bank.nearest(12, torch.tensor(named_color("white")))[0].tolist() == [4, 5]
    # brute force: the same choice as the smallest Lab distance computed row by row
    for name, rgb in NAMED_COLORS.items():
        dists = [float((rgb_to_lab(c) - rgb_to_lab(torch.tensor(rgb))).norm()) for c in bank.colors[12]]
        assert bank.nearest(12, torch.tensor(rgb))[0].tolist() == bank.codes[12][dists.index(min(dists))].tolist(), name
    with pytest.raises(KeyError, match="class 13"):
        bank.nearest(13, torch.zeros(3))
    with pytest.raises(ValueError, match="no colours"):
        CodeBank(bank.codes).nearest(12, torch.zeros(3))
    with pytest.raises(ValueError, match="one \\(M, 3\\) colour per code"):
        CodeBank(bank.codes, {12: torch.zeros(2, 3), 1: torch.zeros(1, 3)})


def test_save_load_round_trip_is_exact_and_plain_json(tmp_path):
    bank = _bank()
    path = save_code_bank(bank, tmp_path / "last.code_bank.json", checkpoint="last.ckpt")
    data = json.loads(path.read_text())
    assert data["format"] == "sdn3d-code-bank" and data["code_dim"] == 2 and data["checkpoint"] == "last.ckpt"
    again = load_code_bank(path)
    assert again.classes == [1, 12]
    for c in bank.classes:
        assert torch.equal(again.codes[c], bank.codes[c]) and torch.equal(again.colors[c], bank.colors[c])
    assert code_bank_path(tmp_path / "checkpoints" / "best-epoch003.ckpt") == \
        tmp_path / "checkpoints" / "best-epoch003.code_bank.json"
    assert not list(tmp_path.glob(".*.tmp"))  # written atomically, nothing left over
    with pytest.raises(ValueError, match="colours"):
        save_code_bank(CodeBank(bank.codes), tmp_path / "x.json")


@pytest.mark.parametrize("content, message", [
    (b"\x00\x01PK not json", "is not a code bank JSON file"),
    (b'{"format": "something else", "version": 1}', "is not a code bank"),
    (b'{"format": "sdn3d-code-bank", "version": 1, "code_dim": 2, "classes": {}}', "non-empty 'classes'"),
    (b'{"format": "sdn3d-code-bank", "version": 1, "code_dim": 2, "classes": {"car": {}}}', "got key 'car'"),
    (b'{"format": "sdn3d-code-bank", "version": 1, "code_dim": 2, "classes": {"12": {"codes": [[1, 2, 3]], '
     b'"colors": [[0, 0, 0]]}}}', "classes.12.codes rows must all have 2 values"),
    (b'{"format": "sdn3d-code-bank", "version": 1, "code_dim": 2, "classes": {"12": {"codes": [[1, NaN]], '
     b'"colors": [[0, 0, 0]]}}}', "finite numbers"),
    (b'{"format": "sdn3d-code-bank", "version": 1, "code_dim": 2, "classes": {"12": {"codes": [[1, 2]], '
     b'"colors": [[0, 0, 0], [1, 1, 1]]}}}', "1 codes but 2 colours"),
])
def test_bad_bank_files_name_the_file_and_the_problem(tmp_path, content, message):
    path = tmp_path / "bank.json"
    path.write_bytes(content)
    with pytest.raises(CodeBankFileError, match=message) as info:
        load_code_bank(path)
    assert "code_bank" in str(info.value) and str(path) in str(info.value) and "\n" not in str(info.value)
    with pytest.raises(CodeBankFileError, match="not found"):
        load_code_bank(tmp_path / "missing.json")


def test_build_code_bank_holds_every_region_code_and_mean_colour():
    torch.manual_seed(0)
    encoder = TextureEncoder(code_dim=3, nef=4, n_downsampling=2)
    L = torch.full((2, 16, 24), 1, dtype=torch.long)
    L[:, 8:] = 5
    L[0, 8:, :8] = 12001
    L[1, 10:, 12:20] = 12002
    image = torch.rand(2, 3, 16, 24)
    batches = [{"image": image[:1], "instance_label_map": L[:1]}, {"image": image[1:], "instance_label_map": L[1:]}]
    bank = build_code_bank(encoder, batches)
    assert bank.classes == [1, 5, 12] and len(bank) == 6 and bank.code_dim == 3
    car0 = L[0] == 12001
    torch.testing.assert_close(bank.colors[12][0], image[0][:, car0].mean(1))
    _, means, _, ids = encoder.encode(image[1:] * 2 - 1, L[1:])
    torch.testing.assert_close(bank.codes[12][1], means[ids.tolist().index(12002)])
    assert not encoder.training
