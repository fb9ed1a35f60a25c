"""The geometric de-renderer network (3D-SDN, Sec. 3.1): ResNet-18 on a masked object crop + its 2D box.

Heads (from a 2-layer MLP on ``[pooled ResNet features, box features]``):

- ``log_scale (N, 3)``: ``log (l, h, w)``;
- ``rotation (N, 4)``: quaternion ``(w, x, y, z)``; with ``rotation="yaw_quaternion"`` only the
  ``(w, y)`` part is predicted (x = z = 0), with ``"full_quaternion"`` (ablation) all four; with ``"multibin"``
  (issue 40) it is the yaw quaternion of the MultiBin head's angle: ``yaw_bins (N, B)`` confidence logits and
  ``yaw_residual (N, B, 2)`` ``(cos, sin)`` residuals of the local orientation (observation angle) ``alpha``
  over ``B`` bins (:mod:`sdn3d.geometric.multibin`; bins centred on ``2 pi i / B``: with 4 bins, the back
  ``-pi/2`` and the front ``+pi/2`` views are bin centres), and ``yaw_ray (N,)`` the angle of the ray through
  the box centre, ``ry = alpha + yaw_ray``;
- ``offset (N, 2)``: projected-centre offset ``e``;
- ``log_distance (N, 1)``: ``log tau`` (or ``log t``, by the encoding; the net does not care);
- ``phi (N, 64, 3)``: mirror-symmetric FFD displacements, predicted as the free half lattice
  ``(N, 32, 3)`` and expanded with :func:`~sdn3d.math3d.ffd.expand_half_ffd` (zeros without FFD);
- ``template_logits (N, T)``: a distribution over the ``T`` mesh templates in ``templates``.

The crop is expected in ``[0, 1]``; ImageNet normalisation happens inside (so pretrained
weights see what they were trained on and callers never normalise).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import torch
from torch import Tensor, nn

from sdn3d.geometric.multibin import bin_centers, decode_multibin
from sdn3d.math3d.encodings import RotationMode, encode_yaw_quaternion
from sdn3d.math3d.ffd import FFD_NUM_HALF, expand_half_ffd
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.nets.resnet import resnet18

__all__ = ["GeometricNet", "box_features", "ray_angle", "yaw_distribution", "OUTPUT_KEYS", "NUM_BOX_FEATURES",
           "ROTATIONS"]

#: Keys of :meth:`GeometricNet.forward`'s output.
OUTPUT_KEYS = ("log_scale", "rotation", "offset", "log_distance", "phi", "template_logits")
#: Rotation encodings of the net (:data:`~sdn3d.math3d.encodings.RotationMode`).
ROTATIONS = ("yaw_quaternion", "full_quaternion", "multibin")
#: Width of :func:`box_features`.
NUM_BOX_FEATURES = 6
_IMAGENET_MEAN = (0.485, 0.456, 0.406)
_IMAGENET_STD = (0.229, 0.224, 0.225)


def _check_rows(name: str, tensor: Tensor, width: int, batch: int | None = None) -> None:
    if tensor.dim() != 2 or tensor.shape[1] != width or (batch is not None and tensor.shape[0] != batch):
        rows = "N" if batch is None else str(batch)
        raise ValueError(f"{name} must have shape ({rows}, {width}), got {tuple(tensor.shape)}")


def box_features(box: Tensor, intrinsics: Tensor) -> Tensor:
    """Resize-invariant description of 2D boxes: ``(N, 4), (N, 4) -> (N, 6)``.

    The box edges in normalised camera coordinates ``((l - cx) / fx, (t - cy) / fy, (r - cx) / fx,
    (b - cy) / fy)`` plus ``log(w2D / fx)`` and ``log(h2D / fy)``. They do not change when the image
    is resized (like ``tau``), so a net trained at one working size or camera transfers to another.

    Args:
        box: ``(N, 4)`` boxes ``(l, t, r, b)`` in pixels of the image ``intrinsics`` describe.
        intrinsics: ``(N, 4)`` ``(fx, fy, cx, cy)`` of that image.
    """
    _check_rows("box", box, 4)
    _check_rows("intrinsics", intrinsics, 4, box.shape[0])
    focal = intrinsics[:, :2].repeat(1, 2)
    edges = (box - intrinsics[:, 2:].repeat(1, 2)) / focal
    # clamp: a degenerate box gives a large negative log instead of -inf.
    size = (edges[:, 2:] - edges[:, :2]).clamp_min(1e-6).log()
    return torch.cat([edges, size], dim=1)


def ray_angle(box: Tensor, intrinsics: Tensor) -> Tensor:
    """``(N,)`` angle ``atan2((u - cx) / fx, 1)`` of the ray through each box's centre column (``ry = alpha + ray``)."""
    u = 0.5 * (box[:, 0] + box[:, 2])
    return torch.atan2((u - intrinsics[:, 2]) / intrinsics[:, 0], torch.ones_like(u))


def yaw_distribution(raw: dict[str, Tensor], ry: Tensor) -> Tensor:
    """How much the MultiBin head believes each of the yaws ``ry (N, K)`` faces the way it predicts: ``(N, K)`` in
    ``[0, 1]``, ``sum_i p_i (1 + cos(ry - yaw_ray - c_i - r_i)) / 2`` over its bins (``p`` the bins' softmax, ``c_i +
    r_i`` each bin's angle). A yaw and its end-for-end flip sum to 1: the appearance's say on front against back.

    Args:
        raw: :meth:`GeometricNet.forward` outputs of a ``"multibin"`` net (``yaw_bins``, ``yaw_residual``,
            ``yaw_ray``).
        ry: ``(N, K)`` yaws (radians, camera frame).
    """
    probs = raw["yaw_bins"].softmax(1)  # (N, B)
    res = raw["yaw_residual"]
    angle = bin_centers(probs.shape[1], probs.device, res.dtype) + torch.atan2(res[..., 1], res[..., 0])  # (N, B)
    alpha = ry - raw["yaw_ray"][:, None]  # (N, K)
    agree = (1 + torch.cos(alpha[:, :, None] - angle[:, None, :])) / 2  # (N, K, B)
    return (agree * probs[:, None, :]).sum(-1)


class GeometricNet(nn.Module):
    """ResNet-18 crop encoder + MLP heads for the object's 3D attributes, shape and mesh choice.

    Args:
        rotation: ``"yaw_quaternion"`` (paper: 2 outputs ``(w, y)``), ``"full_quaternion"`` (4 outputs) or
            ``"multibin"`` (``yaw_bins`` confidences and residuals of the local orientation; module doc).
        yaw_bins, yaw_overlap: the MultiBin head's bins and their overlap (a share of half a bin), ``"multibin"`` only.
        templates: mesh ids (indices into :data:`~sdn3d.meshes.templates.TEMPLATE_NAMES` or a mesh
            bank) the ``template_logits`` refer to; default all 8 templates; one id = single CAD model.
        ffd: predict FFD displacements; False gives ``phi = 0`` (undeformed templates).
        hidden: width of the MLP.
        pretrained: optional local ResNet-18 weights file (torchvision names; ``fc.`` dropped).
        scale_prior: initial ``(l, h, w)`` in metres: the bias of the ``log_scale`` head starts at
            its log, so training starts from a car-sized box instead of a 1 m cube.
    """

    def __init__(
        self,
        rotation: RotationMode = "yaw_quaternion",
        templates: Sequence[int] | None = None,
        ffd: bool = True,
        hidden: int = 256,
        pretrained: str | Path | None = None,
        scale_prior: Sequence[float] = (4.0, 1.6, 1.8),
        yaw_bins: int = 4,
        yaw_overlap: float = 0.1,
    ) -> None:
        super().__init__()
        if rotation not in ROTATIONS:
            raise ValueError(f"rotation must be one of {ROTATIONS}, got {rotation!r}")
        if isinstance(yaw_bins, bool) or int(yaw_bins) != yaw_bins or yaw_bins < 2:
            raise ValueError(f"yaw_bins must be an integer >= 2, got {yaw_bins!r}")
        if not 0.0 <= float(yaw_overlap) < 1.0:
            raise ValueError(f"yaw_overlap must lie in [0, 1), got {yaw_overlap!r}")
        templates = tuple(range(len(TEMPLATE_NAMES))) if templates is None else tuple(int(t) for t in templates)
        if not templates or min(templates) < 0 or len(set(templates)) != len(templates):
            raise ValueError(f"templates must be distinct non-negative mesh ids, got {templates}")
        if hidden <= 0:
            raise ValueError(f"hidden must be positive, got {hidden}")
        if len(scale_prior) != 3 or min(scale_prior) <= 0:
            raise ValueError(f"scale_prior must be three positive lengths (l, h, w), got {tuple(scale_prior)}")
        self.rotation = rotation
        self.yaw_bins, self.yaw_overlap = int(yaw_bins), float(yaw_overlap)
        self.use_ffd = bool(ffd)
        self.register_buffer("templates", torch.tensor(templates, dtype=torch.long), persistent=False)
        self.register_buffer("mean", torch.tensor(_IMAGENET_MEAN).view(1, 3, 1, 1), persistent=False)
        self.register_buffer("std", torch.tensor(_IMAGENET_STD).view(1, 3, 1, 1), persistent=False)
        self.backbone = resnet18(num_classes=None, pretrained=pretrained)
        self.mlp = nn.Sequential(
            nn.Linear(self.backbone.num_features + NUM_BOX_FEATURES, hidden),
            nn.ReLU(inplace=True),
            nn.Linear(hidden, hidden),
            nn.ReLU(inplace=True),
        )
        rot_dim = {"yaw_quaternion": 2, "full_quaternion": 4, "multibin": 3 * self.yaw_bins}[rotation]
        self.heads = nn.ModuleDict({
            "log_scale": nn.Linear(hidden, 3),
            "rotation": nn.Linear(hidden, rot_dim),
            "offset": nn.Linear(hidden, 2),
            "log_distance": nn.Linear(hidden, 1),
        })
        if len(templates) > 1:
            self.heads["template_logits"] = nn.Linear(hidden, len(templates))
        if self.use_ffd:
            self.heads["phi"] = nn.Linear(hidden, FFD_NUM_HALF * 3)
        with torch.no_grad():
            self.heads["log_scale"].bias.copy_(torch.tensor(scale_prior, dtype=torch.float32).log())
            # phi = 0 (the undeformed template) and a uniform mesh choice at the start: the FFD
            # and the mesh choice are only trained by L_reproj / REINFORCE in the joint stage.
            for key in ("phi", "template_logits"):
                if key in self.heads:
                    nn.init.zeros_(self.heads[key].weight)
                    nn.init.zeros_(self.heads[key].bias)

    @property
    def num_templates(self) -> int:
        return int(self.templates.numel())

    def forward(self, crop: Tensor, box: Tensor, intrinsics: Tensor) -> dict[str, Tensor]:
        """Raw outputs (see the module doc for keys and shapes).

        Args:
            crop: ``(N, 3, S, S)`` masked object crops in ``[0, 1]``.
            box: ``(N, 4)`` 2D boxes ``(l, t, r, b)`` in pixels of the image ``intrinsics`` describe.
            intrinsics: ``(N, 4)`` ``(fx, fy, cx, cy)`` of that image.
        """
        if crop.dim() != 4 or crop.shape[1] != 3:
            raise ValueError(f"crop must have shape (N, 3, S, S), got {tuple(crop.shape)}")
        n = crop.shape[0]
        _check_rows("box", box, 4, n)
        _check_rows("intrinsics", intrinsics, 4, n)
        return self.decode(self.features(crop), box, intrinsics)

    def features(self, crop: Tensor) -> Tensor:
        """``(N, F)`` backbone features of ``(N, 3, S, S)`` crops in ``[0, 1]``."""
        return self.backbone((crop - self.mean) / self.std)

    def decode(self, feats: Tensor, box: Tensor, intrinsics: Tensor) -> dict[str, Tensor]:
        """The raw outputs (:meth:`forward`) from ``(N, F)`` backbone features, ``(N, 4)`` boxes and intrinsics."""
        n = feats.shape[0]
        hid = self.mlp(torch.cat([feats, box_features(box, intrinsics).to(feats.dtype)], dim=1))
        rot = self.heads["rotation"](hid)
        out = {key: self.heads[key](hid) for key in ("log_scale", "offset", "log_distance")}
        if self.rotation == "yaw_quaternion":
            zeros = torch.zeros_like(rot[:, :1])
            rot = torch.cat([rot[:, :1], zeros, rot[:, 1:], zeros], dim=1)
        elif self.rotation == "multibin":
            b = self.yaw_bins
            out["yaw_bins"], out["yaw_residual"] = rot[:, :b], rot[:, b:].view(n, b, 2)
            out["yaw_ray"] = ray_angle(box, intrinsics).to(rot.dtype)
            alpha = decode_multibin(out["yaw_bins"], out["yaw_residual"])
            rot = encode_yaw_quaternion(alpha + out["yaw_ray"])
        out["rotation"] = rot
        if self.use_ffd:
            out["phi"] = expand_half_ffd(self.heads["phi"](hid).view(n, FFD_NUM_HALF, 3))
        else:
            out["phi"] = hid.new_zeros(n, 2 * FFD_NUM_HALF, 3)
        if "template_logits" in self.heads:
            out["template_logits"] = self.heads["template_logits"](hid)
        else:
            out["template_logits"] = hid.new_zeros(n, 1)
        return out
