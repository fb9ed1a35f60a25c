"""Free-form deformation (FFD): a 4x4x4 control lattice over the canonical unit box.

A canonical vertex ``v`` in ``[-0.5, 0.5]^3`` has local coordinates ``u = v + 0.5`` in
``[0, 1]^3`` and trivariate cubic Bernstein weights ``B_i(u_x) B_j(u_y) B_k(u_z)`` on the
control points ``P_ijk = (i/3, j/3, k/3) - 0.5``; control point ``(i, j, k)`` has the flat index
``i * 16 + j * 4 + k`` (i along x, j along y, k along z). The deformed vertex is
``sum_ijk B_ijk(v) (P_ijk + phi_ijk)``. Bernstein polynomials reproduce linear functions, so
``sum_ijk B_ijk(v) P_ijk = v`` and the deformation is computed as ``v + basis @ phi``: phi = 0 is
exactly the identity.

Vertices outside the unit box are *not* clamped: the Bernstein polynomials extrapolate
smoothly (the weights still sum to one but some become negative), which keeps the map
smooth for template meshes that overhang the box slightly.

Symmetry: vehicles are mirror-symmetric across the canonical ``z = 0`` plane (width axis).
Control point ``(i, j, k)`` mirrors to ``(i, j, 3 - k)`` with its z displacement negated; a
field with ``phi = mirror(phi)`` keeps a mirror-symmetric mesh symmetric. The network predicts
the 32 free control points with ``k in {0, 1}`` (:func:`half_indices`) and
:func:`expand_half_ffd` builds the symmetric 64-point field.
"""

from __future__ import annotations

import torch
from torch import Tensor, nn

__all__ = [
    "FFD_LATTICE",
    "FFD_NUM_POINTS",
    "FFD_NUM_HALF",
    "bernstein_basis",
    "control_points",
    "ffd_deform",
    "mirror_ffd",
    "symmetrize_ffd",
    "half_indices",
    "expand_half_ffd",
    "FreeFormDeformation",
]

#: Control points per axis (cubic Bernstein basis: degree 3).
FFD_LATTICE = 4
#: Number of control points, 4 ** 3.
FFD_NUM_POINTS = FFD_LATTICE**3
#: Free control points of a mirror-symmetric field (k in {0, 1}).
FFD_NUM_HALF = FFD_NUM_POINTS // 2


def _bernstein_cubic(u: Tensor) -> Tensor:
    """``(...)`` -> ``(..., 4)`` the four cubic Bernstein polynomials at ``u``."""
    s = 1 - u
    return torch.stack([s * s * s, 3 * u * s * s, 3 * u * u * s, u * u * u], dim=-1)


def bernstein_basis(verts: Tensor) -> Tensor:
    """FFD weights of canonical vertices.

    Args:
        verts: ``(..., V, 3)`` canonical vertices (normally in ``[-0.5, 0.5]^3``; outside the
            box the polynomials extrapolate, see the module doc).

    Returns:
        ``(..., V, 64)`` weights ``B_i(x) B_j(y) B_k(z)`` at flat index ``i * 16 + j * 4 + k``;
        every row sums to one.
    """
    if verts.dim() < 2 or verts.shape[-1] != 3:
        raise ValueError(f"verts must have shape (..., V, 3), got {tuple(verts.shape)}")
    b = _bernstein_cubic(verts + 0.5)  # (..., V, 3, 4)
    bx, by, bz = b[..., 0, :], b[..., 1, :], b[..., 2, :]
    # Outer product in (i, j, k) order so that the row-major flatten gives i * 16 + j * 4 + k.
    weights = bx[..., :, None, None] * by[..., None, :, None] * bz[..., None, None, :]
    return weights.flatten(-3)


def control_points(dtype: torch.dtype = torch.float32, device: torch.device | str | None = None) -> Tensor:
    """``(64, 3)`` rest positions ``(i/3, j/3, k/3) - 0.5`` of the control lattice, flat order."""
    axis = torch.arange(FFD_LATTICE, dtype=dtype, device=device) / (FFD_LATTICE - 1) - 0.5
    grid = torch.stack(torch.meshgrid(axis, axis, axis, indexing="ij"), dim=-1)
    return grid.reshape(FFD_NUM_POINTS, 3)


def ffd_deform(verts: Tensor, phi: Tensor, basis: Tensor | None = None) -> Tensor:
    """Deform canonical vertices by control point displacements: ``verts + basis @ phi``.

    Args:
        verts: ``(B, V, 3)`` (or ``(V, 3)``, shared) canonical vertices.
        phi: ``(B, 64, 3)`` control point displacements in canonical units.
        basis: optional precomputed ``bernstein_basis(verts)``, ``(B, V, 64)`` or ``(V, 64)``
            (a mesh bank caches ``(M, V, 64)`` per template and passes ``basis[template_ids]``).
            It must belong to ``verts``; this is not checked.

    Returns:
        ``(B, V, 3)`` deformed vertices.
    """
    if phi.dim() != 3 or phi.shape[-2:] != (FFD_NUM_POINTS, 3):
        raise ValueError(f"phi must have shape (B, {FFD_NUM_POINTS}, 3), got {tuple(phi.shape)}")
    if verts.dim() not in (2, 3) or verts.shape[-1] != 3:
        raise ValueError(f"verts must have shape (B, V, 3) or (V, 3), got {tuple(verts.shape)}")
    if basis is None:
        basis = bernstein_basis(verts)
    elif basis.shape[-2:] != (verts.shape[-2], FFD_NUM_POINTS) or basis.dim() not in (2, 3):
        raise ValueError(f"basis must have shape (B, V, {FFD_NUM_POINTS}) or (V, {FFD_NUM_POINTS}) with "
                         f"V={verts.shape[-2]}, got {tuple(basis.shape)}")
    if basis.dim() == 3 and basis.shape[0] not in (1, phi.shape[0]):
        raise ValueError(f"basis batch {basis.shape[0]} does not match phi batch {phi.shape[0]}; "
                         "index a per-template basis by template id first")
    return verts + basis @ phi


def mirror_ffd(phi: Tensor) -> Tensor:
    """Mirror image across ``z = 0`` of a ``(..., 64, 3)`` field.

    The displacement at ``(i, j, k)`` becomes that of ``(i, j, 3 - k)`` with z negated.
    """
    if phi.dim() < 2 or phi.shape[-2:] != (FFD_NUM_POINTS, 3):
        raise ValueError(f"phi must have shape (..., {FFD_NUM_POINTS}, 3), got {tuple(phi.shape)}")
    grid = phi.reshape(*phi.shape[:-2], FFD_LATTICE, FFD_LATTICE, FFD_LATTICE, 3).flip(-2)
    sign = torch.tensor([1.0, 1.0, -1.0], dtype=phi.dtype, device=phi.device)
    return (grid * sign).reshape(phi.shape)


def symmetrize_ffd(phi: Tensor) -> Tensor:
    """Orthogonal projection onto mirror-symmetric fields: ``(phi + mirror(phi)) / 2``, ``(..., 64, 3)``."""
    return 0.5 * (phi + mirror_ffd(phi))


def half_indices(device: torch.device | str | None = None) -> Tensor:
    """Flat indices ``i * 16 + j * 4 + k`` of the 32 free control points (``k in {0, 1}``).

    Ordered by ``(i, j, k)`` lexicographically, the order :func:`expand_half_ffd` reads its
    input in: ``phi_half = phi[..., half_indices(), :]`` and ``expand_half_ffd(phi_half) == phi``
    for any symmetric ``phi``. The points with ``k in {2, 3}`` are their mirrors.
    """
    idx = torch.arange(FFD_NUM_POINTS, device=device).reshape(FFD_LATTICE, FFD_LATTICE, FFD_LATTICE)
    return idx[..., : FFD_LATTICE // 2].reshape(-1)


def expand_half_ffd(phi_half: Tensor) -> Tensor:
    """Symmetric ``(..., 64, 3)`` field from its free half ``(..., 32, 3)``, in :func:`half_indices` order."""
    if phi_half.dim() < 2 or phi_half.shape[-2:] != (FFD_NUM_HALF, 3):
        raise ValueError(f"phi_half must have shape (..., {FFD_NUM_HALF}, 3), got {tuple(phi_half.shape)}")
    half = phi_half.reshape(*phi_half.shape[:-2], FFD_LATTICE, FFD_LATTICE, FFD_LATTICE // 2, 3)
    sign = torch.tensor([1.0, 1.0, -1.0], dtype=phi_half.dtype, device=phi_half.device)
    full = torch.cat([half, half.flip(-2) * sign], dim=-2)
    return full.reshape(*phi_half.shape[:-2], FFD_NUM_POINTS, 3)


class FreeFormDeformation(nn.Module):
    """Thin module around :func:`ffd_deform` holding precomputed Bernstein weights.

    Args:
        basis: ``(M, V, 64)`` weights of M templates (or ``(V, 64)`` for one), e.g.
            ``bernstein_basis(template_verts)``; kept as a buffer so it follows ``.to(device)``.
        half: if True, ``forward`` takes the 32 free control points ``(B, 32, 3)`` and expands
            them to a mirror-symmetric field; otherwise the full ``(B, 64, 3)``.
    """

    def __init__(self, basis: Tensor, half: bool = False) -> None:
        super().__init__()
        if basis.dim() not in (2, 3) or basis.shape[-1] != FFD_NUM_POINTS:
            raise ValueError(f"basis must have shape (M, V, {FFD_NUM_POINTS}) or (V, {FFD_NUM_POINTS}), "
                             f"got {tuple(basis.shape)}")
        self.register_buffer("basis", basis)
        self.half = half

    def forward(self, verts: Tensor, phi: Tensor, template_ids: Tensor | None = None) -> Tensor:
        """``(B, V, 3)`` deformed vertices.

        Args:
            verts: ``(B, V, 3)`` canonical vertices matching the selected basis.
            phi: ``(B, 64, 3)``, or ``(B, 32, 3)`` when ``half``.
            template_ids: ``(B,)`` long, which template's basis each object uses (needed when
                the buffer holds ``M > 1`` templates).
        """
        basis = self.basis
        if template_ids is not None:
            if basis.dim() != 3:
                raise ValueError("template_ids given but the basis holds a single template (V, 64)")
            basis = basis[template_ids]
        if self.half:
            phi = expand_half_ffd(phi)
        return ffd_deform(verts, phi, basis)
