"""The photo appearance's learnt fill (:mod:`sdn3d.editing.photo.learnt`): shapes, only the hole changes,
determinism, weights files and their errors, its wiring as ``photo.fill=learnt``."""

from __future__ import annotations

import pytest
import torch

from sdn3d.editing.photo.fill import fill_hole
from sdn3d.editing.photo.learnt import (
    WORK_SIDE,
    FillEnsemble,
    FillNet,
    TrainSettings,
    crop_boxes,
    crop_samples,
    default_weights_path,
    learnt_fill,
    load_fill_net,
    net_inputs,
    save_fill_net,
    train_fill_net,
)
from sdn3d.editing.photo.settings import PhotoSettings, PhotoSettingsError


def _picture(height: int = 60, width: int = 90) -> tuple[torch.Tensor, torch.Tensor]:
    gen = torch.Generator().manual_seed(3)
    image = torch.rand(3, height, width, generator=gen) * 0.5 + 0.2
    hole = torch.zeros(height, width, dtype=torch.bool)
    hole[20:40, 30:55] = True
    hole[5:7, 5:8] = True  # a sliver under MIN_PART_PX: left as it is
    return image, hole


def _busy_net(seed: int = 1) -> FillNet:
    """A net whose output is not zero (the trained last layer's place taken by random weights)."""
    torch.manual_seed(seed)
    net = FillNet(4)
    torch.nn.init.normal_(net.out.weight, std=0.05)
    torch.nn.init.constant_(net.out.bias, 0.1)
    return net.eval()


def test_the_correction_changes_only_the_hole_and_keeps_the_shape():
    image, hole = _picture()
    out = learnt_fill(image, hole, _busy_net())
    assert out.shape == image.shape and out.dtype == image.dtype
    big = hole.clone()
    big[5:7, 5:8] = False
    assert torch.equal(out[:, ~big], image[:, ~big])  # outside the large part (the sliver too) bit for bit
    assert float((out - image)[:, big].abs().mean()) > 0.02
    assert float(out.min()) >= 0 and float(out.max()) <= 1


def test_an_untrained_net_is_the_rays_fill_and_the_inputs_have_their_shape():
    image, hole = _picture()
    assert torch.equal(learnt_fill(image, hole, FillNet(4)), image)
    boxes, labels = crop_boxes(hole)
    assert len(boxes) == 1 and int(labels.max()) == 1
    y0, y1, x0, x1 = boxes[0]
    assert y1 - y0 == x1 - x0 and y0 <= 20 and y1 >= 40 and x0 <= 30 and x1 >= 55
    x = net_inputs(image, hole, None, boxes)
    assert x.shape == (1, 7, WORK_SIDE, WORK_SIDE)
    assert FillNet(4)(x).shape == (1, 3, WORK_SIDE, WORK_SIDE)


def _toy_samples() -> tuple:
    """Crops whose truth is the fill 0.2 lighter in the hole (the brightness the rays miss in fog)."""
    parts = []
    for i in range(4):
        image, hole = _picture()
        image = image.roll(7 * i, 2)
        target = torch.where(hole[None], (image + 0.2).clamp(0, 1), image)
        parts.append(crop_samples(image, hole, None, target, i))
    from sdn3d.editing.photo.learnt import FillSamples

    return FillSamples.cat(parts)


def test_training_is_deterministic_given_its_seed_and_learns_a_brightness_offset():
    samples = _toy_samples()
    few = TrainSettings(width=4, steps=5, batch=2, lr=8e-3, seed=5)
    a, b = train_fill_net(samples, few), train_fill_net(samples, few)
    for (name, pa), pb in zip(a.state_dict().items(), b.state_dict().values(), strict=True):
        assert torch.equal(pa, pb), name
    a = train_fill_net(samples, TrainSettings(width=4, steps=25, batch=2, lr=8e-3, seed=5))
    image, hole = _picture()
    big = hole.clone()
    big[5:7, 5:8] = False
    lift = float((learnt_fill(image, hole, a) - image)[:, big].mean())
    assert lift > 0.08  # most of the 0.2 it was shown, from a net that starts at 0


def test_weights_round_trip_and_errors_name_the_file(tmp_path):
    net = _busy_net()
    path = tmp_path / "fill.pt"
    save_fill_net(net, path, {"note": "test"})
    back = load_fill_net(path)
    image, hole = _picture()
    assert torch.allclose(learnt_fill(image, hole, back), learnt_fill(image, hole, net), atol=2e-3)
    with pytest.raises(PhotoSettingsError, match="no weights file .*missing.pt"):
        load_fill_net(tmp_path / "missing.pt")
    (tmp_path / "junk.pt").write_bytes(b"not a torch file")
    with pytest.raises(PhotoSettingsError, match="junk.pt.*not a weights file"):
        load_fill_net(tmp_path / "junk.pt")
    torch.save({"format": "something else"}, tmp_path / "other.pt")
    with pytest.raises(PhotoSettingsError, match="other.pt.*holds no sdn3d-learnt-fill"):
        load_fill_net(tmp_path / "other.pt")
    blob = torch.load(path, weights_only=True)
    blob["members"][0]["width"] = 8
    torch.save(blob, tmp_path / "wrong.pt")
    with pytest.raises(PhotoSettingsError, match="wrong.pt.*do not fit the net"):
        load_fill_net(tmp_path / "wrong.pt")
    del blob["side"]
    torch.save(blob, tmp_path / "sideless.pt")
    with pytest.raises(PhotoSettingsError, match="sideless.pt.*do not fit the net"):
        load_fill_net(tmp_path / "sideless.pt")


def test_a_finer_net_keeps_its_working_side_from_training_to_file_to_drawing(tmp_path):
    image, hole = _picture()
    target = torch.where(hole[None], (image + 0.2).clamp(0, 1), image)
    samples = crop_samples(image, hole, None, target, 0, side=48)
    assert samples.inputs.shape == (1, 7, 48, 48) and samples.target.shape == (1, 3, 96, 96)
    net = train_fill_net(samples, TrainSettings(width=4, steps=2, batch=1, seed=1))
    assert net.side == 48
    torch.nn.init.constant_(net.out.bias, 0.1)
    save_fill_net(net, tmp_path / "fine.pt")
    back = load_fill_net(tmp_path / "fine.pt")
    assert back.side == 48
    assert torch.allclose(learnt_fill(image, hole, back), learnt_fill(image, hole, net), atol=2e-3)
    with pytest.raises(ValueError, match="side must be a multiple of 4"):
        FillNet(4, side=30)


def test_an_ensemble_draws_the_mean_of_its_nets_corrections_and_round_trips(tmp_path):
    image, hole = _picture()
    a, b = _busy_net(1), _busy_net(2)
    both = FillEnsemble([a, b])
    change = learnt_fill(image, hole, both) - image
    mean = ((learnt_fill(image, hole, a) - image) + (learnt_fill(image, hole, b) - image)) / 2
    inside = (image + 0.3 < 1).all(0) & (image - 0.3 > 0).all(0)  # no clamping: the mean of the two corrections
    assert torch.allclose(change[:, inside], mean[:, inside], atol=1e-5)
    save_fill_net(both, tmp_path / "two.pt")
    back = load_fill_net(tmp_path / "two.pt")
    assert len(back.nets) == 2
    assert torch.allclose(learnt_fill(image, hole, back), learnt_fill(image, hole, both), atol=2e-3)
    with pytest.raises(ValueError, match="one working side"):
        FillEnsemble([FillNet(4), FillNet(4, side=48)])


def test_fill_learnt_is_the_rays_fill_corrected_inside_the_hole(tmp_path):
    image, hole = _picture()
    path = tmp_path / "fill.pt"
    save_fill_net(_busy_net(), path)
    rays = fill_hole(image, hole, PhotoSettings(fill="rays"))
    learnt = fill_hole(image, hole, PhotoSettings(fill="learnt", learnt_weights=str(path)))
    assert torch.equal(learnt[:, ~hole], image[:, ~hole])
    assert float((learnt - rays)[:, hole].abs().mean()) > 0.02
    with pytest.raises(PhotoSettingsError, match="no weights file .*nowhere.pt"):
        fill_hole(image, hole, PhotoSettings(fill="learnt", learnt_weights=str(tmp_path / "nowhere.pt")))
    with pytest.raises(PhotoSettingsError, match="learnt_weights must be a file path or null"):
        PhotoSettings(fill="learnt", learnt_weights="")



def test_the_correction_fades_in_from_the_holes_edge():
    from sdn3d.editing.photo.learnt import feather

    image, hole = _picture()
    change = (learnt_fill(image, hole, _busy_net()) - image).abs().mean(0)
    edge, middle = change[20, 30:55].mean(), change[28:32, 40:45].mean()  # the part's first row, its centre
    assert float(edge) < 0.4 * float(middle)
    ramp = feather(hole[15:45, 25:60])
    assert float(ramp[5, 5:30].max()) < 0.5 and float(ramp[15, 17]) == 1.0 and float(ramp[0, 0]) == 0.0


def test_the_packaged_weights_load():
    assert default_weights_path().is_file()
    net = load_fill_net(None)
    assert isinstance(net, FillEnsemble) and all(isinstance(n, FillNet) for n in net.nets) and net.side % 4 == 0


def test_the_counterfactual_bench_lists_the_learnt_fill():
    from sdn3d.evaluation.counterfactual import CounterfactualSettings, methods

    settings = CounterfactualSettings(fills=("rays", "learnt"))
    assert "photo:learnt" in methods(settings, has_generator=False)
