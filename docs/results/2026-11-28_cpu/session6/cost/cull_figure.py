# ruff: noqa: E402, E501, E701, E702
"""Figure: a template's soft silhouette at the fine crop (64 px) drawn with every face, with the faces facing the
camera only, and their difference; the faces each one draws in the title."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import torch

from sdn3d.math3d.transforms import object_to_camera
from sdn3d.meshes.bank import default_bank
from sdn3d.render import SoftSilhouetteSettings, soft_silhouette

bank = default_bank().simplified(600)
verts, faces = bank.gather(torch.tensor([0]))
F = int(bank.num_faces[0]); faces = faces[:, :F]
cam = object_to_camera(verts, torch.tensor([[3.9, 1.5, 1.6]]), torch.tensor([0.6]), torch.tensor([[0.0, 0.4, 9.0]]))
K = torch.tensor([[[80.0, 0, 31.5], [0, 80.0, 31.5], [0, 0, 1]]])
both = soft_silhouette(cam, faces, K, SoftSilhouetteSettings((64, 64)))[0]
front = soft_silhouette(cam, faces, K, SoftSilhouetteSettings((64, 64), cull_backfaces=True))[0]
tri = cam[0][faces[0]]; n = torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1)
nf = int(((n * tri[:, 0]).sum(-1) < 0).sum())
fig, ax = plt.subplots(1, 3, figsize=(10, 3.6))
ax[0].imshow(both, cmap="gray", vmin=0, vmax=1); ax[0].set_title(f"every face ({F} faces)")
ax[1].imshow(front, cmap="gray", vmin=0, vmax=1); ax[1].set_title(f"faces facing the camera ({nf})")
d = (both - front).numpy(); im = ax[2].imshow(d, cmap="magma", vmin=0, vmax=max(d.max(), 1e-6))
ax[2].set_title(f"every face minus front only (max {d.max():.2f})"); fig.colorbar(im, ax=ax[2], fraction=0.046)
for a in ax: a.set_xticks([]); a.set_yticks([])
fig.suptitle("sedan cut to 600 faces, soft silhouette at the fine crop (64 px, sigma 0.25 px^2)")
fig.tight_layout(); fig.savefig(sys.argv[1], dpi=80)
print("front faces", nf, "of", F, "px > 0.5:", int((both > 0.5).sum()), int((front > 0.5).sum()), "sum", float(both.sum()), float(front.sum()))
