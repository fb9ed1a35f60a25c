"""Issue 32, images: the edit path reads its input through the project's one image reader
(``sdn3d.data.imageio.read_rgb``), which converts 16-bit, palette, grey and float images from their own range
or refuses them by name; before, ``PIL.convert("RGB")`` read a 16-bit PNG as white and a float TIFF as black."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from sdn3d.cli._config import compose_config
from sdn3d.data.errors import DataFormatError
from sdn3d.data.imageio import read_rgb
from sdn3d.errors import InputError

# Virtual KITTI's aspect ratio (1242x375 within 2 %): no camera needs to be given
W, H = 83, 25


def _save(path, array, mode=None):
    Image.fromarray(array, mode=mode).save(path) if mode else Image.fromarray(array).save(path)
    return path


def _grey16(path, value):
    image = Image.new("I;16", (W, H))
    image.frombytes(np.full((H, W), value, dtype="<u2").tobytes(), "raw", "I;16")
    image.save(path)
    assert Image.open(path).mode == "I;16"
    return path


def _float_tiff(path, values):
    _save(path, np.asarray(values, dtype=np.float32))
    assert Image.open(path).mode == "F"
    return path


def _load(path, tmp_path):
    from sdn3d.cli.edit import load_input

    cfg = compose_config([f"input.image={path}", f"output_dir={tmp_path / 'out'}", "image_size=[83, 25]"], "edit")
    image, _, _, _ = load_input(cfg)
    return image


# -- the reader --------------------------------------------------------------------------------------


def test_read_rgb_scales_16bit_grey_from_its_range(tmp_path):
    rgb = read_rgb(_grey16(tmp_path / "g16.png", 32768))
    assert rgb.dtype == np.uint8 and rgb.shape == (H, W, 3)
    assert np.all(rgb == 128)  # 32768 / 65535 * 255 = 127.5 -> 128, not clipped to 255
    assert np.all(read_rgb(_grey16(tmp_path / "max.png", 65535)) == 255)
    assert np.all(read_rgb(_grey16(tmp_path / "low.png", 257)) == 1)


def test_read_rgb_scales_float_images_from_0_1(tmp_path):
    values = np.full((H, W), 0.25, np.float32)
    values[0, 0], values[0, 1] = 0.0, 1.0
    rgb = read_rgb(_float_tiff(tmp_path / "f.tif", values))
    assert rgb[0, 0].tolist() == [0, 0, 0] and rgb[0, 1].tolist() == [255, 255, 255]
    assert np.all(rgb[1:] == 64)


@pytest.mark.parametrize("values, match", [
    (np.full((H, W), 300.0), r"values in \[300, 300\].*\[0, 1\]"),
    (np.full((H, W), -0.5), r"values in \[-0.5, -0.5\]"),
    (np.where(np.eye(H, W) > 0, np.nan, 0.5), "non-finite"),
])
def test_read_rgb_refuses_float_images_outside_0_1_by_name(tmp_path, values, match):
    path = _float_tiff(tmp_path / "bad.tif", values)
    with pytest.raises(DataFormatError, match=match) as info:
        read_rgb(path)
    assert str(path) in str(info.value)


def test_read_rgb_refuses_32bit_integer_images_by_name(tmp_path):
    path = _save(tmp_path / "i32.tif", np.full((H, W), 70000, np.int32))
    assert Image.open(path).mode == "I"
    with pytest.raises(DataFormatError, match=r"mode 'I' is not supported") as info:
        read_rgb(path)
    assert str(path) in str(info.value)


def test_read_rgb_converts_palette_grey_bilevel_and_alpha(tmp_path):
    grey = np.full((H, W), 77, np.uint8)
    assert np.all(read_rgb(_save(tmp_path / "l.png", grey)) == 77)
    palette = Image.new("P", (W, H))
    palette.putpalette([10, 20, 30] + [0, 0, 0] * 255)
    palette.save(tmp_path / "p.png")
    assert read_rgb(tmp_path / "p.png")[3, 4].tolist() == [10, 20, 30]
    Image.new("1", (W, H), 1).save(tmp_path / "b.png")
    assert np.all(read_rgb(tmp_path / "b.png") == 255)
    rgba = np.zeros((H, W, 4), np.uint8)
    rgba[..., :3], rgba[..., 3] = (40, 50, 60), 0  # fully transparent: the stored colour is used
    assert read_rgb(_save(tmp_path / "a.png", rgba))[0, 0].tolist() == [40, 50, 60]


# -- the edit path -----------------------------------------------------------------------------------


def test_edit_input_16bit_png_is_not_read_as_white(tmp_path):
    image = _load(_grey16(tmp_path / "g16.png", 16384), tmp_path)
    assert image.shape == (3, 25, 83)
    assert torch_close(image, 64 / 255)  # 16384 / 65535 * 255 = 63.75 -> 64


def test_edit_input_float_tiff_is_not_read_as_black(tmp_path):
    image = _load(_float_tiff(tmp_path / "f.tif", np.full((H, W), 0.5, np.float32)), tmp_path)
    assert torch_close(image, 128 / 255)


def test_edit_input_unsupported_image_is_refused_naming_input_image(tmp_path):
    path = _float_tiff(tmp_path / "hdr.tif", np.full((H, W), 4.0, np.float32))
    with pytest.raises(InputError, match=r"input.image .*hdr.tif.*\[0, 1\]"):
        _load(path, tmp_path)


def test_sdn3d_edit_exits_2_on_an_unsupported_image_and_writes_nothing(tmp_path, capsys):
    import sdn3d.cli.edit as edit

    (tmp_path / "ops.yaml").write_text("- {op: delete, id: 12001}\n")
    path = _float_tiff(tmp_path / "hdr.tif", np.full((H, W), 4.0, np.float32))
    code = edit.main([f"input.image={path}", f"edits={tmp_path / 'ops.yaml'}", f"output_dir={tmp_path / 'out'}"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.startswith("sdn3d-edit: error: input.image") and "float image" in err, err
    assert len(err.splitlines()) == 1 and not (tmp_path / "out").exists()


def test_edit_compose_reads_the_input_through_the_same_reader(tmp_path):
    from sdn3d.cli.edit import _input_picture

    cfg = compose_config([f"input.image={_grey16(tmp_path / 'g16.png', 65535 // 2)}"], "edit")
    picture = _input_picture(cfg, None)
    assert picture.dtype == np.uint8 and picture.shape == (H, W, 3) and np.all(picture == 127)


def torch_close(image, value: float) -> bool:
    return bool((image - value).abs().max() < 1e-5)
