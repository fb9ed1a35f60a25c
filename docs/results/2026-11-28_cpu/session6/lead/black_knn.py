# ruff: noqa
import sys, torch, numpy as np
from PIL import Image
import sdn3d.editing.photo.transfer as T
from sdn3d.scene.io import load_scene
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.meshes.parts import Part
d = sys.argv[1]
scene = load_scene(d + "/scene"); edited = load_scene(d + "/edited_scene")
img = torch.from_numpy(np.asarray(Image.open("tests/data/0006_30-deg-right_00043.png").convert("RGB")).copy()).permute(2,0,1).float()/255
frame = PixelFrame((1242, 375), (624, 192))
s = PhotoSettings()
orig = T._part_colors
def spy(b, s_mesh, visible_px, points, normals, parts, before, src, parts_src, img_flat, settings, body, others=None, max_examples=1500, k=4):
    own, _ = T._part_examples(b, s_mesh, visible_px, before, src, parts_src, img_flat, settings)
    q = (parts == int(Part.BODY)).nonzero().flatten()
    have = (own.part == int(Part.BODY)).nonzero().flatten()
    qf = T._part_features(before, b, points[q], normals[q])
    near = torch.cdist(qf, own.feature[have]).topk(4, largest=False).indices
    chosen = have[near].flatten()
    col = own.color[chosen]
    luma = col @ torch.tensor([0.2126,0.7152,0.0722],dtype=torch.float64)
    print("queries", len(q), "chosen unique", len(chosen.unique()), "chosen luma mean", round(float(luma.mean()),3))
    print("query feature mean", qf.mean(0).numpy().round(2))
    u, c = chosen.unique(return_counts=True)
    top = u[c.argsort(descending=True)[:8]]
    print("top examples features", own.feature[top].numpy().round(2), "colors", own.color[top].numpy().round(2))
    print("example feature mean (all body)", own.feature[have].mean(0).numpy().round(2))
    return orig(b, s_mesh, visible_px, points, normals, parts, before, src, parts_src, img_flat, settings, body, others, max_examples, k)
T._part_colors = spy
r = T.render_photo(img, frame, scene, edited, settings=s)
