"""The geometric branch's 3D attribute targets (3D-SDN, Sec. 3.1) with exact decoders.

For an object with dimensions ``dims = (l, h, w)``, yaw ``ry``, box centre ``c`` (camera
frame) and 2D box ``(l, t, r, b)`` in pixels with centre ``(x2D, y2D)`` and size ``(w2D, h2D)``
(``w2D = r - l``, ``h2D = b - t``: continuous pixel coordinates):

- scale: ``log s`` with ``s = (l, h, w)``;
- rotation ``"yaw_quaternion"`` (paper): ``q = (cos(ry/2), 0, sin(ry/2), 0)`` (w, x, y, z as
  kornia); ``"full_quaternion"`` (ablation): kornia's ``rotation_matrix_to_quaternion(R_y(ry))``,
  whose sign is not canonicalised. Loss ``1 - (q~ . q)^2`` is sign-invariant; ``"multibin"`` (issue 40):
  the target is the yaw quaternion as for ``"yaw_quaternion"``, but the net predicts the local orientation
  (observation angle) as Deep3DBox's MultiBin (bin confidences + residuals, :mod:`sdn3d.geometric.multibin`)
  and its own ``rotation`` output is the yaw quaternion of that angle; its loss is the MultiBin loss
  (:func:`sdn3d.geometric.losses.prediction_losses`), which tells the front from the back, while the
  quaternion loss of an axis (``1 - (q~ . q)^2`` is 0.5 for a flipped car) does so only weakly;
- offset ``e = ((x3D - x2D) / w2D, (y3D - y2D) / h2D)`` with ``(x3D, y3D)`` the projection of ``c``;
- distance ``"log_tau"`` (paper): ``log tau``, ``tau = |c| sqrt((w2D / fx) (h2D / fy))``, which
  does not change when the image (and box) is resized; ``"log_distance"`` (ablation): ``log |c|``.

Decoding inverts this exactly: ``(x3D, y3D) = (x2D + e_x w2D, y2D + e_y h2D)``,
``d = K^-1 (x3D, y3D, 1)``, ``c = t d / |d|``. ``K`` is a pinhole matrix without skew, as
everywhere in sdn3d (see :mod:`sdn3d.math3d.camera`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.math3d.camera import project_points, unproject_pixels
from sdn3d.math3d.rotations import roty, wrap_angle

__all__ = [
    "RotationMode",
    "DistanceMode",
    "AttributeEncoding",
    "box_center_size",
    "encode_log_scale",
    "decode_log_scale",
    "encode_yaw_quaternion",
    "decode_yaw_quaternion",
    "encode_full_quaternion",
    "decode_full_quaternion",
    "encode_offset",
    "encode_distance",
    "decode_distance",
    "decode_center",
    "rotation_loss",
    "encode_attributes",
    "decode_attributes",
]

RotationMode = Literal["yaw_quaternion", "full_quaternion", "multibin"]
DistanceMode = Literal["log_tau", "log_distance"]
_ROTATION_MODES = ("yaw_quaternion", "full_quaternion", "multibin")
_DISTANCE_MODES = ("log_tau", "log_distance")
_TARGET_KEYS = ("log_scale", "rotation", "offset", "log_distance")


# --------------------------------------------------------------------------- validation
def _check_finite(name: str, tensor: Tensor) -> None:
    if not bool(torch.isfinite(tensor).all()):
        raise ValueError(f"{name} contains NaN or infinite values")


def _check_shape(name: str, tensor: Tensor, shape: tuple[int, ...]) -> None:
    if tuple(tensor.shape) != shape:
        raise ValueError(f"{name} must have shape {shape}, got {tuple(tensor.shape)}")


def _batch_K(K: Tensor, batch: int) -> Tensor:
    """``(B, 3, 3)`` view of a ``(3, 3)`` or ``(B, 3, 3)`` calibration, validated."""
    if K.dim() == 2 and K.shape == (3, 3):
        K = K.expand(batch, 3, 3)
    elif K.dim() != 3 or K.shape[1:] != (3, 3) or K.shape[0] not in (1, batch):
        raise ValueError(f"K must have shape (3, 3) or ({batch}, 3, 3), got {tuple(K.shape)}")
    K = K.expand(batch, 3, 3)
    _check_finite("K", K)
    if bool((K[:, 0, 0] <= 0).any()) or bool((K[:, 1, 1] <= 0).any()):
        raise ValueError("K must have positive focal lengths fx = K[0, 0] and fy = K[1, 1]")
    return K


def box_center_size(box2d: Tensor) -> tuple[Tensor, Tensor]:
    """Centre ``(B, 2)`` and size ``(B, 2)`` (``w2D = r - l``, ``h2D = b - t``) of ``(B, 4)`` boxes.

    Raises:
        ValueError: on a wrong shape, NaN/inf, or a non-positive width or height.
    """
    if box2d.dim() != 2 or box2d.shape[-1] != 4:
        raise ValueError(f"box2d must have shape (B, 4) as (l, t, r, b), got {tuple(box2d.shape)}")
    _check_finite("box2d", box2d)
    size = box2d[:, 2:] - box2d[:, :2]
    if bool((size <= 0).any()):
        raise ValueError("box2d must have positive width (r - l) and height (b - t)")
    return (box2d[:, :2] + box2d[:, 2:]) / 2, size


# --------------------------------------------------------------------------- scale
def encode_log_scale(dims: Tensor) -> Tensor:
    """``log (l, h, w)``: ``(B, 3)`` -> ``(B, 3)``; dims must be positive and finite."""
    if dims.dim() != 2 or dims.shape[-1] != 3:
        raise ValueError(f"dims must have shape (B, 3) as (l, h, w), got {tuple(dims.shape)}")
    _check_finite("dims", dims)
    if bool((dims <= 0).any()):
        raise ValueError("dims must be positive (l, h, w in metres)")
    return dims.log()


def decode_log_scale(log_scale: Tensor) -> Tensor:
    """``exp``: ``(B, 3)`` log dimensions -> ``(B, 3)`` dims ``(l, h, w)``."""
    return log_scale.exp()


# --------------------------------------------------------------------------- rotation
def encode_yaw_quaternion(ry: Tensor) -> Tensor:
    """Unit quaternion of ``R_y(ry)`` as ``(cos(ry/2), 0, sin(ry/2), 0)``: ``(B,)`` -> ``(B, 4)``.

    For ``ry`` in ``[-pi, pi)`` the real part is non-negative.
    """
    half = ry / 2
    zeros = torch.zeros_like(ry)
    return torch.stack([half.cos(), zeros, half.sin(), zeros], dim=-1)


def decode_yaw_quaternion(q: Tensor) -> Tensor:
    """Yaw from the y-rotation component of any (unnormalised) quaternion ``(..., 4)``.

    ``ry = wrap(2 atan2(q_y, q_w))`` in ``[-pi, pi)``; atan2 ignores the common scale, so
    normalising is implicit, and ``-q`` gives the same yaw (``2 atan2`` differs by ``2 pi``).
    The x and z components are ignored (the projection onto rotations about y).
    """
    return wrap_angle(2 * torch.atan2(q[..., 2], q[..., 0]))


def encode_full_quaternion(ry: Tensor) -> Tensor:
    """Full ``(B, 4)`` quaternion (w, x, y, z) of ``R_y(ry)`` as kornia computes it (sign not fixed)."""
    from kornia.geometry.conversions import rotation_matrix_to_quaternion  # the ablation only: not at start-up

    return rotation_matrix_to_quaternion(roty(ry))


def decode_full_quaternion(q: Tensor) -> Tensor:
    """Yaw of a general ``(..., 4)`` quaternion (w, x, y, z), normalised first.

    The quaternion becomes a rotation matrix R (kornia); the yaw is the heading of the
    rotated vehicle front ``R e_x`` in the ground (x-z) plane. ``R_y(ry) e_x = (cos ry, 0, -sin ry)``,
    so ``ry = atan2(-R[2, 0], R[0, 0])``, exact for pure y rotations.
    """
    from kornia.geometry.conversions import quaternion_to_rotation_matrix  # the ablation only: not at start-up

    rot = quaternion_to_rotation_matrix(F.normalize(q, dim=-1))
    return wrap_angle(torch.atan2(-rot[..., 2, 0], rot[..., 0, 0]))


def rotation_loss(pred: Tensor, target: Tensor, rotation: RotationMode = "yaw_quaternion") -> Tensor:
    """Per-object sign-invariant quaternion loss ``1 - (q~ . q)^2``: ``(B, 4), (B, 4)`` -> ``(B,)``.

    ``q~`` is the normalised prediction. With ``"yaw_quaternion"`` the prediction is first
    projected onto rotations about y by keeping only its ``(w, y)`` components (the decoder
    reads only those), so the loss is over that 2-D part; with ``"full_quaternion"`` it is over
    all 4 components. The target is assumed unit norm (as the encoders give it). ``"multibin"`` scores its
    quaternion output as ``"yaw_quaternion"`` does (its training loss is MultiBin's, on the net's bin outputs).
    """
    if rotation not in _ROTATION_MODES:
        raise ValueError(f"rotation must be one of {_ROTATION_MODES}, got {rotation!r}")
    if pred.shape != target.shape or pred.shape[-1] != 4:
        raise ValueError(f"pred and target must both have shape (B, 4), got {tuple(pred.shape)} "
                         f"and {tuple(target.shape)}")
    if rotation in ("yaw_quaternion", "multibin"):
        pred = pred[..., [0, 2]]
        target = target[..., [0, 2]]
    # eps keeps the gradient finite at a zero prediction.
    dot = (F.normalize(pred, dim=-1, eps=1e-8) * target).sum(-1)
    return 1 - dot.square()


# --------------------------------------------------------------------------- translation
def encode_offset(center: Tensor, box2d: Tensor, K: Tensor) -> Tensor:
    """Offset ``((x3D - x2D) / w2D, (y3D - y2D) / h2D)`` of the projected centre: ``(B, 2)``.

    Args:
        center: ``(B, 3)`` box centres, ``z > 0``.
        box2d: ``(B, 4)`` boxes ``(l, t, r, b)`` in pixels.
        K: ``(3, 3)`` or ``(B, 3, 3)``.
    """
    box_c, box_s = box_center_size(box2d)
    _check_center(center, box2d.shape[0])
    K = _batch_K(K, box2d.shape[0])
    return (project_points(center, K) - box_c) / box_s


def _check_center(center: Tensor, batch: int) -> None:
    _check_shape("center", center, (batch, 3))
    _check_finite("center", center)
    if bool((center[:, 2] <= 0).any()):
        raise ValueError("center must lie in front of the camera (z > 0)")


def _box_scale(box_size: Tensor, K: Tensor) -> Tensor:
    """``sqrt((w2D / fx) (h2D / fy))``: the box size in normalised image units, ``(B,)``."""
    return torch.sqrt(box_size[:, 0] / K[:, 0, 0] * (box_size[:, 1] / K[:, 1, 1]))


def encode_distance(center: Tensor, box2d: Tensor, K: Tensor, distance: DistanceMode = "log_tau") -> Tensor:
    """``log tau`` (``tau = |c| sqrt((w2D/fx)(h2D/fy))``) or ``log |c|``: ``(B, 1)``."""
    if distance not in _DISTANCE_MODES:
        raise ValueError(f"distance must be one of {_DISTANCE_MODES}, got {distance!r}")
    _, box_s = box_center_size(box2d)
    _check_center(center, box2d.shape[0])
    K = _batch_K(K, box2d.shape[0])
    log_t = center.norm(dim=-1).log()
    if distance == "log_tau":
        log_t = log_t + _box_scale(box_s, K).log()
    return log_t.unsqueeze(-1)


def decode_distance(
    log_distance: Tensor, box2d: Tensor, K: Tensor, distance: DistanceMode = "log_tau"
) -> Tensor:
    """Distance ``t = |c|`` ``(B,)`` from the ``(B, 1)`` target of :func:`encode_distance`."""
    if distance not in _DISTANCE_MODES:
        raise ValueError(f"distance must be one of {_DISTANCE_MODES}, got {distance!r}")
    _, box_s = box_center_size(box2d)
    _check_shape("log_distance", log_distance, (box2d.shape[0], 1))
    log_t = log_distance[:, 0]
    if distance == "log_tau":
        log_t = log_t - _box_scale(box_s, _batch_K(K, box2d.shape[0])).log()
    return log_t.exp()


def decode_center(offset: Tensor, t: Tensor, box2d: Tensor, K: Tensor) -> Tensor:
    """Box centre ``c = t d / |d|`` with ``d = K^-1 (x2D + e_x w2D, y2D + e_y h2D, 1)``: ``(B, 3)``.

    Args:
        offset: ``(B, 2)`` offsets ``e``.
        t: ``(B,)`` distances ``|c|``.
        box2d: ``(B, 4)``; K: ``(3, 3)`` or ``(B, 3, 3)``.
    """
    box_c, box_s = box_center_size(box2d)
    batch = box2d.shape[0]
    _check_shape("offset", offset, (batch, 2))
    _check_shape("t", t, (batch,))
    uv = box_c + offset * box_s
    ray = unproject_pixels(uv, torch.ones_like(uv[:, :1]), _batch_K(K, batch))
    return t.unsqueeze(-1) * F.normalize(ray, dim=-1)


# --------------------------------------------------------------------------- all attributes
def encode_attributes(
    dims: Tensor,
    ry: Tensor,
    center: Tensor,
    box2d: Tensor,
    K: Tensor,
    rotation: RotationMode = "yaw_quaternion",
    distance: DistanceMode = "log_tau",
) -> dict[str, Tensor]:
    """All targets of B objects; see :meth:`AttributeEncoding.encode`."""
    if rotation not in _ROTATION_MODES:
        raise ValueError(f"rotation must be one of {_ROTATION_MODES}, got {rotation!r}")
    box_center_size(box2d)  # validates box2d before its batch size is trusted
    batch = box2d.shape[0]
    _check_shape("ry", ry, (batch,))
    _check_finite("ry", ry)
    encode_rot = encode_full_quaternion if rotation == "full_quaternion" else encode_yaw_quaternion
    return {
        "log_scale": encode_log_scale(dims),
        "rotation": encode_rot(wrap_angle(ry)),
        "offset": encode_offset(center, box2d, K),
        "log_distance": encode_distance(center, box2d, K, distance),
    }


def decode_attributes(
    targets: dict[str, Tensor],
    box2d: Tensor,
    K: Tensor,
    rotation: RotationMode = "yaw_quaternion",
    distance: DistanceMode = "log_tau",
) -> tuple[Tensor, Tensor, Tensor]:
    """Invert :func:`encode_attributes`: ``(dims (B, 3), ry (B,) in [-pi, pi), center (B, 3))``."""
    if rotation not in _ROTATION_MODES:
        raise ValueError(f"rotation must be one of {_ROTATION_MODES}, got {rotation!r}")
    missing = [key for key in _TARGET_KEYS if key not in targets]
    if missing:
        raise ValueError(f"targets is missing keys {missing}; expected {list(_TARGET_KEYS)}")
    box_center_size(box2d)
    batch = box2d.shape[0]
    for key, size in zip(_TARGET_KEYS, (3, 4, 2, 1), strict=True):
        _check_shape(f"targets[{key!r}]", targets[key], (batch, size))
        _check_finite(f"targets[{key!r}]", targets[key])
    decode_rot = decode_full_quaternion if rotation == "full_quaternion" else decode_yaw_quaternion
    t = decode_distance(targets["log_distance"], box2d, K, distance)
    return (
        decode_log_scale(targets["log_scale"]),
        decode_rot(targets["rotation"]),
        decode_center(targets["offset"], t, box2d, K),
    )


@dataclass(frozen=True)
class AttributeEncoding:
    """The target parameterisation of the geometric branch, with its ablation variants.

    Args:
        rotation: ``"yaw_quaternion"`` (paper), ``"full_quaternion"`` (ablation) or ``"multibin"`` (targets as
            ``"yaw_quaternion"``; the net's MultiBin head and loss, issue 40).
        distance: ``"log_tau"`` (paper, resize-invariant) or ``"log_distance"`` (ablation, ``log |c|``).

    Example:
        >>> import torch
        >>> encoding = AttributeEncoding()
        >>> K = torch.tensor([[725.0, 0.0, 620.5], [0.0, 725.0, 187.0], [0.0, 0.0, 1.0]])  # Virtual KITTI
        >>> dims, ry = torch.tensor([[4.0, 1.5, 1.8]]), torch.tensor([0.5])  # one car: (l, h, w) m, yaw
        >>> center = torch.tensor([[2.0, 1.0, 15.0]])  # box centre, camera frame
        >>> box2d = torch.tensor([[640.0, 180.0, 780.0, 260.0]])  # its 2D box (l, t, r, b)
        >>> targets = encoding.encode(dims, ry, center, box2d, K)
        >>> {key: tuple(value.shape) for key, value in targets.items()}
        {'log_scale': (1, 3), 'rotation': (1, 4), 'offset': (1, 2), 'log_distance': (1, 1)}
        >>> dims2, ry2, center2 = encoding.decode(targets, box2d, K)
        >>> dims2.shape, ry2.shape, center2.shape
        (torch.Size([1, 3]), torch.Size([1]), torch.Size([1, 3]))
        >>> round(ry2.item(), 4), torch.allclose(dims2, dims), torch.allclose(center2, center, atol=1e-4)
        (0.5, True, True)
    """

    rotation: RotationMode = "yaw_quaternion"
    distance: DistanceMode = "log_tau"

    def __post_init__(self) -> None:
        if self.rotation not in _ROTATION_MODES:
            raise ValueError(f"rotation must be one of {_ROTATION_MODES}, got {self.rotation!r}")
        if self.distance not in _DISTANCE_MODES:
            raise ValueError(f"distance must be one of {_DISTANCE_MODES}, got {self.distance!r}")

    def encode(self, dims: Tensor, ry: Tensor, center: Tensor, box2d: Tensor, K: Tensor) -> dict[str, Tensor]:
        """Targets of B objects.

        Args:
            dims: ``(B, 3)`` as ``(l, h, w)``, positive.
            ry: ``(B,)`` yaw (any range; wrapped to ``[-pi, pi)``).
            center: ``(B, 3)`` box centres, ``z > 0``.
            box2d: ``(B, 4)`` 2D boxes ``(l, t, r, b)`` in pixels, positive size.
            K: ``(3, 3)`` or ``(B, 3, 3)`` calibration of the image the boxes live in.

        Returns:
            ``log_scale (B, 3)``, ``rotation (B, 4)``, ``offset (B, 2)``, ``log_distance (B, 1)``
            (``log tau`` or ``log t`` by :attr:`distance`).
        """
        return encode_attributes(dims, ry, center, box2d, K, self.rotation, self.distance)

    def decode(self, targets: dict[str, Tensor], box2d: Tensor, K: Tensor) -> tuple[Tensor, Tensor, Tensor]:
        """``(dims (B, 3), ry (B,), center (B, 3))`` from targets (or predictions) of :meth:`encode`."""
        return decode_attributes(targets, box2d, K, self.rotation, self.distance)

    def rotation_loss(self, pred: Tensor, target: Tensor) -> Tensor:
        """``(B,)`` sign-invariant quaternion loss of this variant; see :func:`rotation_loss`."""
        return rotation_loss(pred, target, self.rotation)
