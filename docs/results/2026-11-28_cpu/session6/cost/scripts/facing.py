# ruff: noqa: E402, E501, E701, E702
import torch

from sdn3d.math3d.transforms import object_to_camera
from sdn3d.meshes.bank import default_bank
from sdn3d.render._common import face_vertices, project_vertices, twice_area

bank = default_bank()
verts, faces = bank.gather(torch.tensor([0])); faces = faces[:, :int(bank.num_faces[0])]
K = torch.tensor([[[60.0, 0, 32], [0, 60.0, 32], [0, 0, 1]]])
cam = object_to_camera(verts, torch.tensor([[3.9, 1.5, 1.6]]), torch.tensor([0.7]), torch.tensor([[0.5, 0.6, 8.0]]))
tri = face_vertices(cam, faces)[0]  # (F, 3, 3)
n = torch.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1)
front3d = (n * tri[:, 0]).sum(-1) < 0
scr, _ = project_vertices(cam, K, 0.1)
a2 = twice_area(face_vertices(scr, faces).reshape(-1, 3, 2))
print("front3d", int(front3d.sum()), "of", len(front3d), "agree with a2>0:", float(((a2 > 0) == front3d).float().mean()), "with a2<0:", float(((a2 < 0) == front3d).float().mean()))
