"""Raw :class:`~sdn3d.geometric.model.GeometricNet` outputs -> metric object attributes.

:func:`decode_outputs` is differentiable (the training loop uses it for the reprojection loss, the
per-image refinement optimises through it); :func:`template_distribution` scatters the mesh logits
over mesh ids.
"""

from __future__ import annotations

from collections.abc import Mapping

import torch
from torch import Tensor

from sdn3d.math3d.camera import as_intrinsics_matrix
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.math3d.transforms import center_to_bottom
from sdn3d.meshes.templates import TEMPLATE_NAMES

__all__ = ["template_distribution", "decode_outputs"]


def template_distribution(logits: Tensor, templates: Tensor, num_meshes: int = len(TEMPLATE_NAMES)) -> Tensor:
    """Softmax of ``(N, T)`` logits scattered to ``(N, num_meshes)`` mesh-id probabilities."""
    probs = logits.softmax(dim=-1)
    out = probs.new_zeros(probs.shape[0], num_meshes)
    return out.index_copy(1, templates.to(probs.device), probs)


def decode_outputs(
    raw: Mapping[str, Tensor],
    box: Tensor,
    K: Tensor,
    encoding: AttributeEncoding | None = None,
    templates: Tensor | None = None,
) -> dict[str, Tensor]:
    """Metric attributes from raw outputs (differentiable w.r.t. ``raw``).

    Args:
        raw: :meth:`GeometricNet.forward` outputs.
        box: ``(N, 4)`` 2D boxes in pixels of the image ``K`` describes.
        K: that image's intrinsics, ``(N, 4)`` ``(fx, fy, cx, cy)``, ``(N, 3, 3)`` or ``(3, 3)``.
        encoding: the target parameterisation the net was trained with (paper default).
        templates: ``(T,)`` mesh ids of the logits (``GeometricNet.templates``); default ``arange(T)``.

    Returns:
        ``dims (N, 3)`` as ``(l, h, w)``; ``ry (N,)``; ``center (N, 3)`` box centre and ``location
        (N, 3)`` bottom-face centre (camera frame); ``template_id (N,)`` (argmax mesh id);
        ``template_probs (N, M)`` with ``M = max(8, max id + 1)``; ``phi (N, 64, 3)``; for a ``"multibin"`` net
        also its ``yaw_bins``, ``yaw_residual`` and ``yaw_ray`` as they are (the appearance's belief in any yaw,
        :func:`sdn3d.geometric.model.yaw_distribution`, the test-time fit's front/back cue).
    """
    encoding = encoding or AttributeEncoding()
    n = box.shape[0]
    dims, ry, center = encoding.decode(raw, box, as_intrinsics_matrix(K, n).to(box.dtype))
    logits = raw["template_logits"]
    if templates is None:
        templates = torch.arange(logits.shape[1], device=logits.device)
    probs = template_distribution(logits, templates, max(len(TEMPLATE_NAMES), int(templates.max()) + 1))
    extra = {k: raw[k] for k in ("yaw_bins", "yaw_residual", "yaw_ray") if k in raw}
    return {
        **extra,
        "dims": dims,
        "ry": ry,
        "center": center,
        "location": center_to_bottom(center, dims[:, 1]),
        "template_id": templates.to(logits.device)[logits.argmax(dim=1)],
        "template_probs": probs,
        "phi": raw["phi"],
    }
