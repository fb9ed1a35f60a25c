# ruff: noqa: E402, E501, E701, E702
"""Are the bank's meshes (full, cut to 250 and 600 faces) closed and consistently wound? Does the union of the
front-facing faces' hard raster equal the whole mesh's?"""

import torch

from sdn3d.math3d.transforms import object_to_camera
from sdn3d.meshes.bank import default_bank
from sdn3d.render._common import face_vertices, project_vertices, twice_area
from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings

bank = default_bank()
for nf in (0, 250, 600):
    b = bank.simplified(nf) if nf else bank
    for i in range(len(b)):
        m = b.to_trimesh(i)
        verts, faces = b.gather(torch.tensor([i]))
        F = int(b.num_faces[i]); faces = faces[:, :F]
        K = torch.tensor([[[60.0, 0, 32], [0, 60.0, 32], [0, 0, 1]]])
        diffs = []
        for ry in (0.3, 1.2, 2.5, -1.0):
            cam = object_to_camera(verts, torch.tensor([[3.9, 1.5, 1.6]]), torch.tensor([ry]), torch.tensor([[0.5, 0.6, 8.0]]))
            full = rasterize_meshes(cam, faces, K, RasterSettings((64, 64))).mask
            scr, ok = project_vertices(cam, K, 0.1)
            a2 = twice_area(face_vertices(scr, faces).reshape(-1, 3, 2))
            for sign in (1, -1):
                keep = faces[:, (a2 * sign > 0)]
                part = rasterize_meshes(cam, keep, K, RasterSettings((64, 64))).mask
                diffs.append(int((full ^ part).sum()))
        print(nf, b.names[i], F, "watertight", m.is_watertight, "winding", m.is_winding_consistent, "vol", round(float(m.volume), 2), "xor px (ry x sign)", diffs, "full px", int(full.sum()))
