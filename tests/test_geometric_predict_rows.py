"""An object's geometric prediction is its own: the same bits whatever else is predicted with it.

PyTorch's CPU convolutions sum in another order for batches under 4 rows, and its matrix products for other numbers of
rows. On the real frame in ``tests/data`` the red car's prediction moved in its 7th digit when the black car was boxed
too, and the fit's search then chose another template for it: in the editor, boxing a second car changed the first.
:meth:`GeometricPredictor.predict` runs the backbone on at least :data:`~sdn3d.geometric.predict.MIN_NET_ROWS` rows
and the fully connected layers on blocks of exactly that many.
"""

from __future__ import annotations

import pytest
import torch
from helpers.tiny_models import geometric_net

from sdn3d.geometric.model import GeometricNet
from sdn3d.geometric.predict import MIN_NET_ROWS, GeometricPredictor


def _inputs(n: int) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    g = torch.Generator().manual_seed(3)
    crop = torch.rand(n, 3, 32, 32, generator=g)
    box = torch.tensor([100.0, 80.0, 180.0, 140.0]) + torch.rand(n, 4, generator=g) * 20
    intrinsics = torch.tensor([[720.0, 720.0, 620.0, 187.0]]).expand(n, 4)
    return crop, box, intrinsics


def test_an_objects_prediction_is_the_same_bits_alone_and_with_others():
    torch.manual_seed(0)
    predictor = GeometricPredictor(geometric_net())
    crop, box, intrinsics = _inputs(6)
    mask = torch.ones(6, 1, 32, 32)
    alone = predictor.predict(crop[:1], mask[:1], box[:1], intrinsics[:1])
    for n in (2, 3, MIN_NET_ROWS, 6):
        together = predictor.predict(crop[:n], mask[:n], box[:n], intrinsics[:n])
        assert set(together) == set(alone)
        for key, value in alone.items():
            assert together[key].shape[0] == n, key
            assert torch.equal(together[key][:1], value), f"{key} with {n - 1} other objects"


@pytest.mark.parametrize("threads", [1, 2])
def test_predictions_are_the_same_bits_in_any_batch_of_a_full_size_net(threads: int):
    """The fully connected layers at the shipped width (256 hidden): with 12 objects predicted at once, the first n
    objects' outputs equal their outputs when predicted alone together, for every n, and in reverse order (on main,
    with two threads, an 11-object batch moved every output of its rows in the last bits)."""
    before = torch.get_num_threads()
    torch.set_num_threads(threads)
    try:
        torch.manual_seed(0)
        predictor = GeometricPredictor(GeometricNet(hidden=256))
        crop, box, intrinsics = _inputs(12)
        mask = torch.ones(12, 1, 32, 32)
        every = predictor.predict(crop, mask, box, intrinsics)
        keys = [k for k, v in every.items() if torch.is_tensor(v) and v.shape[:1] == (12,)]
        assert {"dims", "ry", "location"} <= set(keys)
        for n in range(1, 12):
            some = predictor.predict(crop[:n], mask[:n], box[:n], intrinsics[:n])
            for key in keys:
                assert torch.equal(some[key], every[key][:n]), f"{key}: the first {n} of 12 objects"
        back = list(range(11, -1, -1))
        reverse = predictor.predict(crop[back], mask[back], box[back], intrinsics[back])
        for key in keys:
            assert torch.equal(reverse[key], every[key][back]), f"{key} in reverse order"
    finally:
        torch.set_num_threads(before)
