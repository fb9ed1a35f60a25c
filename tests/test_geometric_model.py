"""GeometricNet, decoding, the checkpoint predictor and rendering predictions into scene maps."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.geometric import GeometricNet, GeometricPredictor, box_features
from sdn3d.geometric.decode import decode_outputs
from sdn3d.math3d.camera import VKITTI_INTRINSICS, as_intrinsics_matrix
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.math3d.ffd import mirror_ffd
from sdn3d.math3d.rotations import wrap_angle
from sdn3d.math3d.transforms import project_box
from sdn3d.meshes.templates import TEMPLATE_NAMES

INTR = VKITTI_INTRINSICS.resized(624, 192)
K_VEC = torch.tensor([INTR.fx, INTR.fy, INTR.cx, INTR.cy])


def _objects(n: int = 5, seed: int = 0):
    """Plausible cars in front of the camera with their tight 2D boxes."""
    g = torch.Generator().manual_seed(seed)
    dims = torch.tensor([4.2, 1.6, 1.8]) * (0.8 + 0.4 * torch.rand(n, 3, generator=g))
    ry = (torch.rand(n, generator=g) * 2 - 1) * math.pi
    center = torch.stack([torch.rand(n, generator=g) * 8 - 4, 0.8 + 0.2 * torch.rand(n, generator=g),
                          8 + 20 * torch.rand(n, generator=g)], 1)
    box = project_box(dims, ry, center, INTR.matrix())
    return dims, ry, center, box, K_VEC.expand(n, 4)


def test_box_features_do_not_change_when_the_image_is_resized():
    _, _, _, box, intr = _objects()
    sx, sy = 0.5, 1.5
    # Resizing maps u' + 0.5 = (u + 0.5) sx (pixel-centre convention) for boxes and principal points alike.
    scale = torch.tensor([sx, sy, sx, sy])
    box2 = (box + 0.5) * scale - 0.5
    intr2 = torch.stack([intr[:, 0] * sx, intr[:, 1] * sy, (intr[:, 2] + 0.5) * sx - 0.5,
                         (intr[:, 3] + 0.5) * sy - 0.5], 1)
    torch.testing.assert_close(box_features(box2, intr2), box_features(box, intr), rtol=1e-5, atol=1e-5)
    with pytest.raises(ValueError, match="intrinsics"):
        box_features(box, intr[:2])


def test_net_outputs_shapes_symmetry_and_initial_state():
    net = GeometricNet().eval()
    _, _, _, box, intr = _objects(3)
    with torch.no_grad():
        out = net(torch.rand(3, 3, 64, 64), box, intr)
    assert out["log_scale"].shape == (3, 3) and out["offset"].shape == (3, 2)
    assert out["log_distance"].shape == (3, 1) and out["template_logits"].shape == (3, 8)
    assert out["rotation"].shape == (3, 4)
    assert (out["rotation"][:, [1, 3]] == 0).all()  # yaw quaternion: no x / z component
    assert out["phi"].shape == (3, 64, 3)
    # Zero-initialised FFD and mesh heads: undeformed templates and a uniform choice at the start.
    assert (out["phi"] == 0).all() and (out["template_logits"] == 0).all()
    torch.testing.assert_close(out["log_scale"].mean(0), torch.tensor([4.0, 1.6, 1.8]).log(), atol=0.5, rtol=0)
    with torch.no_grad():
        net.heads["phi"].weight.normal_()
        phi = net(torch.rand(3, 3, 64, 64), box, intr)["phi"]
    assert phi.abs().max() > 0
    torch.testing.assert_close(mirror_ffd(phi), phi)  # mirror-symmetric by construction

    full = GeometricNet(rotation="full_quaternion").eval()
    with torch.no_grad():
        assert (full(torch.rand(3, 3, 64, 64), box, intr)["rotation"][:, [1, 3]] != 0).all()
    single = GeometricNet(templates=[TEMPLATE_NAMES.index("van")], ffd=False).eval()
    assert "template_logits" not in single.heads and "phi" not in single.heads
    with torch.no_grad():
        out = single(torch.rand(3, 3, 64, 64), box, intr)
        dec = decode_outputs(out, box, intr, templates=single.templates)
    assert (out["phi"] == 0).all() and dec["template_id"].tolist() == [5, 5, 5]
    assert (dec["template_probs"][:, 5] == 1).all()


def test_net_rejects_bad_input():
    net = GeometricNet()
    _, _, _, box, intr = _objects(2)
    with pytest.raises(ValueError, match="crop"):
        net(torch.rand(2, 1, 64, 64), box, intr)
    with pytest.raises(ValueError, match="box"):
        net(torch.rand(2, 3, 64, 64), box[:1], intr)
    with pytest.raises(ValueError, match="templates"):
        GeometricNet(templates=[1, 1])


@pytest.mark.parametrize("rotation", ["yaw_quaternion", "full_quaternion"])
@pytest.mark.parametrize("distance", ["log_tau", "log_distance"])
def test_decode_inverts_the_targets(rotation, distance):
    dims, ry, center, box, intr = _objects()
    enc = AttributeEncoding(rotation, distance)
    raw = enc.encode(dims, ry, center, box, as_intrinsics_matrix(intr))
    raw.update(phi=torch.zeros(5, 64, 3), template_logits=torch.randn(5, 8))
    out = decode_outputs(raw, box, intr, enc)
    torch.testing.assert_close(out["dims"], dims, rtol=1e-5, atol=1e-5)
    torch.testing.assert_close(wrap_angle(out["ry"] - ry), torch.zeros(5), rtol=0, atol=1e-4)
    torch.testing.assert_close(out["center"], center, rtol=1e-4, atol=1e-4)
    torch.testing.assert_close(out["location"][:, 1] - out["center"][:, 1], dims[:, 1] / 2)
    assert torch.equal(out["template_id"], raw["template_logits"].argmax(1))
    torch.testing.assert_close(out["template_probs"].sum(1), torch.ones(5))


def test_predictor_from_checkpoint_matches_the_net(tmp_path):
    net = GeometricNet(rotation="full_quaternion").eval()
    with torch.no_grad():
        net.heads["template_logits"].bias.copy_(torch.arange(8.0))
    ckpt = {"state_dict": {f"net.{k}": v for k, v in net.state_dict().items()} | {"baseline.value": torch.zeros(())},
            "hyper_parameters": {"rotation": "full_quaternion", "distance": "log_distance", "hidden": 256}}
    torch.save(ckpt, tmp_path / "geo.ckpt")
    predictor = GeometricPredictor.from_checkpoint(tmp_path / "geo.ckpt")
    assert predictor.encoding == AttributeEncoding("full_quaternion", "log_distance")
    _, _, _, box, intr = _objects(4)
    crop, mask = torch.rand(4, 3, 32, 32), (torch.rand(4, 1, 32, 32) > 0.3).float()
    out = predictor.predict(crop, mask, box, intr)
    with torch.no_grad():
        expected = decode_outputs(net(crop * mask, box, intr), box, intr, predictor.encoding)
    for key in ("dims", "ry", "center", "location", "template_probs", "phi"):
        torch.testing.assert_close(out[key], expected[key])
    assert out["template_id"].tolist() == [7] * 4
    crop_intr = torch.tensor([[60.0, 60.0, 15.5, 15.5]]).expand(4, 4)
    sil = predictor.predict(crop, mask, box, intr, crop_intr)["silhouette"]
    assert sil.shape == (4, 32, 32) and 0 <= float(sil.min()) and float(sil.max()) <= 1

    torch.save({"state_dict": {}}, tmp_path / "empty.ckpt")
    with pytest.raises(ValueError, match="net"):
        GeometricPredictor.from_checkpoint(tmp_path / "empty.ckpt")
    with pytest.raises(ValueError, match="does not exist"):
        GeometricPredictor.from_checkpoint(tmp_path / "missing.ckpt")


