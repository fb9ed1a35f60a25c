# ruff: noqa
"""demo_recolor.py OUT.png: the session-9 idle demo's car 12002 recoloured red (its saved scene and source frame),
with the code on PYTHONPATH; writes the recoloured crop and the recolour's stats."""
import sys, json, numpy as np, torch
from PIL import Image
from sdn3d.scene.io import load_scene
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo.transfer import render_photo
from sdn3d.editing.photo.settings import PhotoSettings
D = "/tmp/s9data/lead/demo_idle/edits"
scene = load_scene(D + "/scene")
src = np.asarray(Image.open(D + "/source.png").convert("RGB"))
original = torch.from_numpy(src).permute(2, 0, 1)
transform = PixelFrame((src.shape[1], src.shape[0]), tuple(scene.image_size) if hasattr(scene, "image_size") else (624, 192))
res = render_photo(original, transform, scene, scene, settings=PhotoSettings(), recolor={12002: (0.8, 0.1, 0.1)})
img = res.image.permute(1, 2, 0).numpy()
Image.fromarray(img).save(sys.argv[1])
print(json.dumps(res.objects.get(12002, {}).get("recolor") if hasattr(res, "objects") else res.summary(), default=str)[:500])
if len(sys.argv) > 2:
    import sdn3d.editing.photo.transfer as T
    o = T._recolor
    def wrap(out, source, owner, recolor, objects, warnings, parts=None):
        m = owner == 12002
        p = parts[m]
        print("car pixels", int(m.sum()), "part counts", {int(k): int((p == k).sum()) for k in p.unique()})
        vis = np.zeros((*owner.shape, 3), np.uint8)
        cols = {-1: (60, 60, 60), 0: (255, 0, 0), 1: (0, 255, 255), 2: (255, 255, 0), 3: (255, 255, 255), 4: (255, 0, 255), 5: (0, 255, 0)}
        for k, c in cols.items():
            vis[(m & (parts == k)).numpy()] = c
        Image.fromarray(vis[100:192, 140:320]).resize((720, 368), Image.NEAREST).save(sys.argv[2])
        return o(out, source, owner, recolor, objects, warnings, parts)
    T._recolor = wrap
    render_photo(original, transform, scene, scene, settings=PhotoSettings(), recolor={12002: (0.8, 0.1, 0.1)})
