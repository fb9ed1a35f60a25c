"""Near-plane clipping of triangle meshes (the project's rasterizer culls faces that cross it)."""

from __future__ import annotations

import torch
from torch import Tensor

__all__ = ["clip_near"]


def clip_near(verts: Tensor, faces: Tensor, near: float) -> tuple[Tensor, Tensor, Tensor]:
    """Clip triangles against the plane ``z = near`` (keep ``z >= near``), vectorised.

    A triangle with one vertex in front becomes one triangle, with two in front a quad (two
    triangles); winding is preserved. New vertices are appended after ``verts``.

    Args:
        verts: ``(V, 3)`` camera-frame vertices.
        faces: ``(F, 3)`` int64.
        near: clipping plane.

    Returns:
        ``verts (V', 3)``, ``faces (F', 3)`` and ``parent (F',)``: the input face of each output face.
    """
    tri = verts[faces]  # (F, 3, 3)
    inside = tri[..., 2] >= near
    count = inside.sum(1)
    whole = (count == 3).nonzero().squeeze(1)
    one = (count == 1).nonzero().squeeze(1)
    two = (count == 2).nonzero().squeeze(1)
    out_faces, out_parent, new_verts = [faces[whole]], [whole], []
    base = verts.shape[0]
    for ids, odd_inside in ((one, True), (two, False)):
        if ids.numel() == 0:
            continue
        # Rotate each face so the odd vertex (the lone inside or lone outside one) comes first.
        odd = (inside[ids] == odd_inside).float().argmax(1)
        order = (odd.unsqueeze(1) + torch.arange(3, device=verts.device)) % 3
        idx = torch.gather(faces[ids], 1, order)
        p = verts[idx]  # (n, 3, 3)
        t1 = (near - p[:, 0, 2]) / (p[:, 1, 2] - p[:, 0, 2])
        t2 = (near - p[:, 0, 2]) / (p[:, 2, 2] - p[:, 0, 2])
        i01 = p[:, 0] + t1.unsqueeze(1) * (p[:, 1] - p[:, 0])
        i02 = p[:, 0] + t2.unsqueeze(1) * (p[:, 2] - p[:, 0])
        i01[:, 2] = near  # exact, so the rasterizer's near test never drops a clipped vertex
        i02[:, 2] = near
        n = ids.numel()
        a = base + torch.arange(n, device=verts.device)
        b = a + n
        new_verts += [i01, i02]
        base += 2 * n
        if odd_inside:
            out_faces.append(torch.stack([idx[:, 0], a, b], 1))
            out_parent.append(ids)
        else:
            out_faces += [torch.stack([a, idx[:, 1], idx[:, 2]], 1), torch.stack([a, idx[:, 2], b], 1)]
            out_parent += [ids, ids]
    return torch.cat([verts, *new_verts]), torch.cat(out_faces), torch.cat(out_parent)
