"""Silhouettes for fitting: the soft one, or the hard one with the soft one's gradient (straight-through).

The soft silhouette's L1 optimum is not the true silhouette. With ``A = 1 - prod_j (1 - D_j)`` every contour
edge is shared by two or more faces, so the mass the aggregation puts outside a silhouette is several times the
single-edge mass inside it: on synthetic cars at their true pose, template and FFD, the soft L1 to the true
mask is smallest at about 0.97 of the true size (64-px crops, ``sigma = 0.25`` px^2; 0.93 at ``sigma = 1``),
while the hard mismatch is smallest at 1.00. Fitting on the soft L1 therefore pulls every object smaller than
the paper's hard reprojection error wants.

:func:`straight_through_silhouette` draws the hard z-buffer silhouette in the forward pass (the value the
paper's renderer, Kato's NMR, also draws) and takes the soft silhouette's gradient in the backward pass:
``S = S_soft + (S_hard - S_soft).detach()``. The L1 to a mask then *is* the hard mismatch, its gradient is
``sign(S_hard - mask)`` carried through the soft edges, and it vanishes exactly where the hard silhouette
matches the mask: the fitted size is unbiased up to the pixel grid.
"""

from __future__ import annotations

import torch
from torch import Tensor

from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings, SoftSilhouetteSettings
from sdn3d.render.soft import soft_silhouette

__all__ = ["SILHOUETTES", "straight_through_silhouette", "silhouette"]

#: The silhouettes a fit can use: ``"soft"`` (SoftRas aggregation, biased small under L1) or
#: ``"straight_through"`` (hard forward, soft backward).
SILHOUETTES = ("soft", "straight_through")


def straight_through_silhouette(verts: Tensor, faces: Tensor, K: Tensor, settings: SoftSilhouetteSettings) -> Tensor:
    """Hard silhouettes ``(N, H, W)`` in ``{0, 1}`` whose gradient is the soft silhouette's.

    Args:
        verts: ``(N, V, 3)`` camera-frame vertices; gradients flow to them (and to ``K``) through the soft
            silhouette.
        faces: ``(N, F, 3)`` or shared ``(F, 3)`` vertex indices; padding faces ``(0, 0, 0)``.
        K: ``(3, 3)`` or per-mesh ``(N, 3, 3)`` intrinsics of each image (zero skew).
        settings: the soft silhouette's settings; the hard one uses its ``image_size`` and ``near``.

    Example:
        >>> import torch
        >>> from sdn3d.render import SoftSilhouetteSettings, straight_through_silhouette
        >>> verts = torch.tensor([[[-3.0, -3.0, 5.0], [3.0, -3.0, 5.0], [0.0, 3.0, 5.0]]], requires_grad=True)
        >>> faces = torch.tensor([[0, 1, 2]])
        >>> K = torch.tensor([[10.0, 0.0, 7.5], [0.0, 10.0, 7.5], [0.0, 0.0, 1.0]])
        >>> s = straight_through_silhouette(verts, faces, K, SoftSilhouetteSettings(image_size=(16, 16)))
        >>> int(s.sum()), sorted(s.unique().tolist())  # the hard silhouette's 72 pixel centres
        (72, [0.0, 1.0])
        >>> s.sum().backward(); bool(verts.grad.abs().sum() > 0)
        True
    """
    soft = soft_silhouette(verts, faces, K, settings)
    with torch.no_grad():
        hard = rasterize_meshes(verts.detach(), faces, K.detach(), RasterSettings(settings.image_size,
                                                                                  near=settings.near)).mask
    # Exactly the hard values (x + (1 - x) and x - x round to 1 and 0 for x in [0, 1]).
    return soft + (hard.to(soft.dtype) - soft).detach()


def silhouette(kind: str, verts: Tensor, faces: Tensor, K: Tensor, settings: SoftSilhouetteSettings) -> Tensor:
    """The silhouette ``kind`` (one of :data:`SILHOUETTES`) of each mesh, ``(N, H, W)``."""
    if kind == "soft":
        return soft_silhouette(verts, faces, K, settings)
    if kind == "straight_through":
        return straight_through_silhouette(verts, faces, K, settings)
    raise ValueError(f"silhouette must be one of {SILHOUETTES}, got {kind!r}")
