"""Tests of the geometric branch's attribute targets and their exact decoders."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.math3d import VKITTI_INTRINSICS, observation_angle, project_points, wrap_angle
from sdn3d.math3d.encodings import (
    AttributeEncoding,
    decode_full_quaternion,
    decode_yaw_quaternion,
    encode_full_quaternion,
    encode_yaw_quaternion,
    rotation_loss,
)
from sdn3d.math3d.transforms import box_corners, from_kitti_fields, project_box

F64 = torch.float64
VARIANTS = [
    AttributeEncoding(rotation, distance)
    for rotation in ("yaw_quaternion", "full_quaternion")
    for distance in ("log_tau", "log_distance")
]
VARIANT_IDS = [f"{v.rotation}-{v.distance}" for v in VARIANTS]


def random_objects(batch: int, dtype: torch.dtype = F64) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """Dims 1-5 m, yaw in [-pi, pi), centres x in [-15, 15], y ~ 1, z in [3, 60]."""
    dims = torch.empty(batch, 3, dtype=F64).uniform_(1, 5)
    ry = torch.empty(batch, dtype=F64).uniform_(-math.pi, math.pi)
    center = torch.stack(
        [
            torch.empty(batch, dtype=F64).uniform_(-15, 15),
            1 + 0.2 * torch.randn(batch, dtype=F64),
            torch.empty(batch, dtype=F64).uniform_(3, 60),
        ],
        -1,
    )
    # Boxes close to the camera could reach behind it; push those back so every corner has z > 0.
    center[:, 2] = torch.maximum(center[:, 2], dims.norm(dim=-1) / 2 + 0.5)
    return dims.to(dtype), ry.to(dtype), center.to(dtype)


def objects_with_boxes(batch: int, dtype: torch.dtype = F64):
    dims, ry, center = random_objects(batch)
    K = VKITTI_INTRINSICS.matrix(F64)
    box = project_box(dims, ry, center, K)
    return dims.to(dtype), ry.to(dtype), center.to(dtype), box.to(dtype), K.to(dtype)


def yaw_error(a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    return wrap_angle(a - b).abs()


@pytest.mark.parametrize("enc", VARIANTS, ids=VARIANT_IDS)
@pytest.mark.parametrize("dtype,tol", [(torch.float64, 1e-9), (torch.float32, 1e-4)])
def test_round_trip(enc: AttributeEncoding, dtype: torch.dtype, tol: float) -> None:
    dims, ry, center, box, K = objects_with_boxes(256, dtype)
    targets = enc.encode(dims, ry, center, box, K)
    assert {k: tuple(v.shape) for k, v in targets.items()} == {
        "log_scale": (256, 3), "rotation": (256, 4), "offset": (256, 2), "log_distance": (256, 1)}
    assert all(v.dtype == dtype for v in targets.values())
    dims2, ry2, center2 = enc.decode(targets, box, K)
    torch.testing.assert_close(dims2, dims, atol=tol, rtol=0)
    assert yaw_error(ry2, ry).max().item() < tol
    torch.testing.assert_close(center2, center, atol=tol, rtol=0)
    assert bool(((ry2 >= -math.pi) & (ry2 < math.pi)).all())


def test_target_values_follow_the_definitions() -> None:
    dims, ry, center, box, K = objects_with_boxes(32)
    t = AttributeEncoding().encode(dims, ry, center, box, K)
    torch.testing.assert_close(t["log_scale"], dims.log())
    q = torch.stack([(ry / 2).cos(), torch.zeros_like(ry), (ry / 2).sin(), torch.zeros_like(ry)], -1)
    torch.testing.assert_close(t["rotation"], q)
    uv = project_points(center, K)
    w, h = box[:, 2] - box[:, 0], box[:, 3] - box[:, 1]
    torch.testing.assert_close(t["offset"][:, 0], (uv[:, 0] - (box[:, 0] + box[:, 2]) / 2) / w)
    torch.testing.assert_close(t["offset"][:, 1], (uv[:, 1] - (box[:, 1] + box[:, 3]) / 2) / h)
    tau = center.norm(dim=-1) * torch.sqrt((w / 725.0) * (h / 725.0))
    torch.testing.assert_close(t["log_distance"][:, 0], tau.log())
    plain = AttributeEncoding(distance="log_distance").encode(dims, ry, center, box, K)
    torch.testing.assert_close(plain["log_distance"][:, 0], center.norm(dim=-1).log())


def test_tau_and_offset_invariant_under_resize() -> None:
    dims, ry, center, box, K = objects_with_boxes(64)
    small = VKITTI_INTRINSICS.resized(624, 192)
    sx, sy = 624 / 1242, 192 / 375
    scale = torch.tensor([sx, sy, sx, sy], dtype=F64)
    box_small = (box + 0.5) * scale - 0.5  # pixel edges scale, centres at integers
    enc = AttributeEncoding()
    full = enc.encode(dims, ry, center, box, K)
    resized = enc.encode(dims, ry, center, box_small, small.matrix(F64))
    torch.testing.assert_close(resized["log_distance"], full["log_distance"], atol=1e-12, rtol=0)
    torch.testing.assert_close(resized["offset"], full["offset"], atol=1e-12, rtol=0)
    # The plain log distance is trivially invariant, but the pixel box size is not: tau is the point.
    assert not torch.allclose(box_small[:, 2] - box_small[:, 0], box[:, 2] - box[:, 0])
    _, _, center_small = enc.decode(resized, box_small, small.matrix(F64))
    torch.testing.assert_close(center_small, center, atol=1e-9, rtol=0)


def test_batched_K_matches_shared_K() -> None:
    dims, ry, center, box, K = objects_with_boxes(5)
    enc = AttributeEncoding()
    a = enc.encode(dims, ry, center, box, K)
    b = enc.encode(dims, ry, center, box, K.expand(5, 3, 3))
    for key in a:
        torch.testing.assert_close(a[key], b[key])


def test_full_quaternion_is_yaw_quaternion_up_to_sign() -> None:
    ry = torch.empty(200, dtype=F64).uniform_(-math.pi, math.pi)
    full = encode_full_quaternion(ry)
    yaw = encode_yaw_quaternion(ry)
    dot = (full * yaw).sum(-1)
    torch.testing.assert_close(dot.abs(), torch.ones_like(dot), atol=1e-12, rtol=0)
    torch.testing.assert_close(full.norm(dim=-1), torch.ones_like(dot))


@pytest.mark.parametrize("decode", [decode_yaw_quaternion, decode_full_quaternion])
def test_yaw_decoders_accept_unnormalised_and_negated(decode) -> None:
    ry = torch.empty(50, dtype=F64).uniform_(-math.pi, math.pi)
    q = encode_yaw_quaternion(ry)
    for scale in (0.1, 3.0, -1.0, -7.5):
        assert yaw_error(decode(q * scale), ry).max().item() < 1e-9


def test_full_decoder_reads_heading_of_tilted_rotation() -> None:
    # A small roll about the vehicle's length axis must not change the decoded heading.
    from kornia.geometry.conversions import axis_angle_to_rotation_matrix, rotation_matrix_to_quaternion

    from sdn3d.math3d import roty

    ry = torch.tensor([0.4, -2.0, 3.0], dtype=F64)
    roll = axis_angle_to_rotation_matrix(torch.tensor([[0.2, 0.0, 0.0]] * 3, dtype=F64))
    q = rotation_matrix_to_quaternion(roty(ry) @ roll)
    assert yaw_error(decode_full_quaternion(q), ry).max().item() < 1e-9


def test_rotation_loss_properties() -> None:
    ry = torch.empty(20, dtype=F64).uniform_(-math.pi, math.pi)
    for mode in ("yaw_quaternion", "full_quaternion"):
        target = encode_yaw_quaternion(ry) if mode == "yaw_quaternion" else encode_full_quaternion(ry)
        zero = torch.zeros(20, dtype=F64)
        torch.testing.assert_close(rotation_loss(target, target, mode), zero, atol=1e-12, rtol=0)
        torch.testing.assert_close(rotation_loss(-2.5 * target, target, mode), zero, atol=1e-12, rtol=0)
        # Yaw off by pi: orthogonal quaternions, maximal loss 1; off by d: sin^2(d / 2).
        flipped = encode_yaw_quaternion(ry + math.pi)
        torch.testing.assert_close(rotation_loss(flipped, target, mode), zero + 1, atol=1e-12, rtol=0)
        off = encode_yaw_quaternion(ry + 0.5)
        torch.testing.assert_close(rotation_loss(off, target, mode), zero + math.sin(0.25) ** 2)
    # The yaw variant ignores x, z (its decoder does); the full variant penalises them.
    target = encode_yaw_quaternion(ry)
    tilted = target + torch.tensor([0.0, 0.5, 0.0, 0.5], dtype=F64)
    assert rotation_loss(tilted, target, "yaw_quaternion").abs().max().item() < 1e-12
    assert bool((rotation_loss(tilted, target, "full_quaternion") > 0.1).all())


def test_rotation_loss_gradient_finite() -> None:
    target = encode_yaw_quaternion(torch.empty(6, dtype=F64).uniform_(-math.pi, math.pi))
    pred = torch.randn(6, 4, dtype=F64)
    pred[0] = 0.0  # degenerate prediction
    pred[1] = target[1]  # exact hit
    pred[2] = -target[2]
    for mode in ("yaw_quaternion", "full_quaternion"):
        p = pred.clone().requires_grad_(True)
        rotation_loss(p, target, mode).sum().backward()
        assert p.grad is not None and bool(torch.isfinite(p.grad).all())
        assert p.grad[3:].abs().sum().item() > 0
    p = torch.randn(4, 4, dtype=F64, requires_grad=True)
    assert torch.autograd.gradcheck(lambda x: rotation_loss(x, target[:4], "full_quaternion"), (p,))


def test_decode_is_differentiable() -> None:
    dims, ry, center, box, K = objects_with_boxes(3)
    enc = AttributeEncoding()
    targets = enc.encode(dims, ry, center, box, K)
    keys = list(targets)
    leaves = [targets[k].clone().requires_grad_(True) for k in keys]

    def fn(*xs):
        d, r, c = enc.decode(dict(zip(keys, xs, strict=True)), box, K)
        return d, r, c

    assert torch.autograd.gradcheck(fn, tuple(leaves))


def test_decode_then_encode_reproduces_targets() -> None:
    # Arbitrary network outputs decode to a geometry whose encoding is those outputs.
    _, _, _, box, K = objects_with_boxes(16)
    enc = AttributeEncoding()
    pred = {
        "log_scale": torch.randn(16, 3, dtype=F64),
        "rotation": encode_yaw_quaternion(torch.empty(16, dtype=F64).uniform_(-math.pi, math.pi)),
        "offset": 0.3 * torch.randn(16, 2, dtype=F64),
        "log_distance": torch.randn(16, 1, dtype=F64),
    }
    again = enc.encode(*enc.decode(pred, box, K), box, K)
    for key in pred:
        torch.testing.assert_close(again[key], pred[key], atol=1e-9, rtol=0)


def test_empty_batch() -> None:
    enc = AttributeEncoding()
    e = torch.zeros(0, dtype=F64)
    targets = enc.encode(e.reshape(0, 3), e, e.reshape(0, 3), e.reshape(0, 4), VKITTI_INTRINSICS.matrix(F64))
    dims, ry, center = enc.decode(targets, e.reshape(0, 4), VKITTI_INTRINSICS.matrix(F64))
    assert dims.shape == (0, 3) and ry.shape == (0,) and center.shape == (0, 3)


def test_validation_errors() -> None:
    dims, ry, center, box, K = objects_with_boxes(4)
    enc = AttributeEncoding()
    bad_box = box.clone()
    bad_box[1, 2] = bad_box[1, 0]
    with pytest.raises(ValueError, match="box2d must have positive width"):
        enc.encode(dims, ry, center, bad_box, K)
    with pytest.raises(ValueError, match="dims must be positive"):
        enc.encode(-dims, ry, center, box, K)
    nan_center = center.clone()
    nan_center[0, 0] = float("nan")
    with pytest.raises(ValueError, match="center contains NaN"):
        enc.encode(dims, ry, nan_center, box, K)
    with pytest.raises(ValueError, match="ry contains NaN"):
        enc.encode(dims, ry * float("nan"), center, box, K)
    with pytest.raises(ValueError, match="in front of the camera"):
        enc.encode(dims, ry, center * torch.tensor([1.0, 1.0, -1.0], dtype=F64), box, K)
    with pytest.raises(ValueError, match="K must have shape"):
        enc.encode(dims, ry, center, box, K[:2])
    with pytest.raises(ValueError, match="box2d must have shape"):
        enc.encode(dims, ry, center, box[:, :3], K)
    targets = enc.encode(dims, ry, center, box, K)
    with pytest.raises(ValueError, match="missing keys"):
        enc.decode({"log_scale": targets["log_scale"]}, box, K)
    targets["offset"] = targets["offset"] * float("nan")
    with pytest.raises(ValueError, match="offset"):
        enc.decode(targets, box, K)
    with pytest.raises(ValueError, match="rotation must be one of"):
        AttributeEncoding(rotation="euler")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="distance must be one of"):
        AttributeEncoding(distance="depth")  # type: ignore[arg-type]


# A Virtual KITTI 1.3.1 motgt line (header below). The 2D box is the box of the projected 3D box
# rounded to integer pixels (the real files box the visible instance pixels, so they are never
# larger); alpha is wrap(ry - atan2(x3d, z3d)) rounded to 6 decimals, as in the files.
MOTGT_HEADER = (
    "frame tid label truncated occluded alpha l t r b w3d h3d l3d x3d y3d z3d ry rx rz "
    "truncr occupr orig_label moving model color"
)
MOTGT_LINE = (
    "0 0 Car 0 0 -1.762509 487 186 586 257 1.632196 1.484728 3.880452 -2.113549 1.469946 "
    "17.344936 -1.883765 0 0 0 0.916 Car 1 Hatchback Black"
)


def parse_motgt_line(header: str, line: str) -> dict[str, str]:
    names, values = header.split(), line.split()
    assert len(names) == len(values)
    return dict(zip(names, values, strict=True))


def test_vkitti_motgt_line_round_trip() -> None:
    rec = parse_motgt_line(MOTGT_HEADER, MOTGT_LINE)
    num = {k: torch.tensor([float(rec[k])], dtype=F64) for k in
           ("alpha", "l", "t", "r", "b", "w3d", "h3d", "l3d", "x3d", "y3d", "z3d", "ry")}
    assert abs(wrap_angle(num["alpha"] - observation_angle(num["ry"], num["x3d"], num["z3d"])).item()) < 1e-3
    dims, ry, center = from_kitti_fields(*(num[k] for k in ("w3d", "h3d", "l3d", "x3d", "y3d", "z3d", "ry")))
    box = torch.cat([num[k] for k in ("l", "t", "r", "b")]).unsqueeze(0)
    K = VKITTI_INTRINSICS.matrix(F64)
    # The file's box is consistent with the 3D box to within the pixel rounding.
    torch.testing.assert_close(box, project_box(dims, ry, center, K).round(), atol=0, rtol=0)
    for enc in VARIANTS:
        dims2, ry2, center2 = enc.decode(enc.encode(dims, ry, center, box, K), box, K)
        torch.testing.assert_close(box_corners(dims2, ry2, center2), box_corners(dims, ry, center),
                                   atol=1e-5, rtol=0)
