"""Table-2 metrics of the geometric branch: functional forms and torchmetrics accumulation."""

from __future__ import annotations

import math

import pytest
import torch
from kornia.geometry.conversions import axis_angle_to_rotation_matrix

from sdn3d.geometric import (
    DistanceErrorMetric,
    GeometricMetrics,
    MeshSelectionAccuracy,
    OrientationSimilarity,
    ReprojectionErrorMetric,
    distance_error,
    orientation_similarity,
    predicted_rotation,
    scale_error,
)
from sdn3d.math3d.encodings import encode_full_quaternion
from sdn3d.math3d.rotations import roty


def test_orientation_similarity_is_half_one_plus_cos_of_the_geodesic_angle():
    ry = torch.tensor([0.0, 1.0, -2.0, 3.0])
    delta = torch.tensor([0.0, math.pi / 2, math.pi, 0.3])
    sim = orientation_similarity(roty(ry + delta), roty(ry))
    torch.testing.assert_close(sim, (1 + torch.cos(delta)) / 2, atol=1e-6, rtol=0)
    # Any axis: a tilt of theta about x scores (1 + cos theta) / 2 as well.
    tilt = axis_angle_to_rotation_matrix(torch.tensor([[0.4, 0.0, 0.0]]))
    torch.testing.assert_close(orientation_similarity(tilt @ roty(ry[:1]), roty(ry[:1])),
                               torch.tensor([(1 + math.cos(0.4)) / 2]), atol=1e-6, rtol=0)
    with pytest.raises(ValueError, match="pred_rot"):
        orientation_similarity(torch.eye(3), roty(ry))


def test_predicted_rotation_per_mode():
    ry = torch.tensor([0.7, -2.0])
    torch.testing.assert_close(predicted_rotation(torch.zeros(2, 4), ry, "yaw_quaternion"), roty(ry))
    q = encode_full_quaternion(ry) * torch.tensor([[3.0], [-0.5]])  # unnormalised, sign flipped
    torch.testing.assert_close(predicted_rotation(q, torch.zeros(2), "full_quaternion"), roty(ry), atol=1e-6,
                               rtol=0)


def test_distance_and_scale_errors():
    c = torch.tensor([[3.0, 1.0, 20.0], [0.0, 1.0, 10.0]])
    torch.testing.assert_close(distance_error(c * torch.tensor([[1.1], [0.5]]), c),
                               torch.tensor([math.log(1.1), math.log(2.0)]))
    d = torch.tensor([[4.0, 1.5, 1.8]])
    torch.testing.assert_close(scale_error(d + torch.tensor([[0.3, 0.0, 0.4]]), d), torch.tensor([0.5]))


def test_metrics_accumulate_over_batches():
    m = DistanceErrorMetric()
    c = torch.tensor([[0.0, 1.0, 10.0]])
    m.update(c * math.e, c)
    m.update(c, c)
    m.update(c, c)
    assert math.isclose(float(m.compute()), 1 / 3, rel_tol=1e-6)
    acc = MeshSelectionAccuracy()
    acc.update(torch.tensor([1, 2, 3]), torch.tensor([1, -1, 4]))  # one right of two labelled
    acc.update(torch.tensor([0]), torch.tensor([0]))
    assert math.isclose(float(acc.compute()), 2 / 3, rel_tol=1e-6)
    empty = MeshSelectionAccuracy()
    empty.update(torch.tensor([1]), torch.tensor([-1]))
    assert math.isnan(float(empty.compute()))  # no object with a known template
    rep = ReprojectionErrorMetric()
    sil = torch.zeros(2, 2, 2)
    mask = torch.ones(2, 1, 2, 2)
    ignore = torch.zeros(2, 1, 2, 2)
    ignore[0, 0, 0] = 1.0  # 6 of 8 pixels count, all wrong by 1
    rep.update(sil, mask, ignore)
    rep.update(torch.ones(1, 2, 2), torch.ones(1, 2, 2))  # 4 more pixels, all right
    assert math.isclose(float(rep.compute()), 6 / 10, rel_tol=1e-6)
    o = OrientationSimilarity()
    o.update(roty(torch.tensor([0.0, math.pi])), roty(torch.zeros(2)))
    assert math.isclose(float(o.compute()), 0.5, abs_tol=1e-6)


def test_geometric_metrics_collection():
    metrics = GeometricMetrics()
    ry = torch.tensor([0.2, -1.0])
    center = torch.tensor([[1.0, 1.0, 10.0], [-2.0, 1.0, 20.0]])
    dims = torch.tensor([[4.0, 1.5, 1.8], [4.2, 1.6, 1.7]])
    target = {"ry": ry, "center": center, "dims": dims, "template_id": torch.tensor([3, -1]),
              "mask": torch.ones(2, 1, 4, 4)}
    pred = {"rot": roty(ry), "center": center, "dims": dims, "template_id": torch.tensor([3, 0])}
    metrics.update(pred, target, silhouette=torch.ones(2, 4, 4))
    values = metrics.compute()
    assert math.isclose(float(values["orientation_similarity"]), 1.0, abs_tol=1e-6)
    assert float(values["distance_error"]) < 1e-6 and float(values["scale_error"]) == 0.0
    assert float(values["reprojection_error"]) == 0.0 and float(values["mesh_accuracy"]) == 1.0
    metrics.reset()
    with pytest.warns(UserWarning, match="before the ``update``"):
        assert math.isnan(float(metrics["scale_error"].compute()))
