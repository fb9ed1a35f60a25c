# ruff: noqa: E401, E402, E501, E701, E702, I001, F401
"""exp.py: wraps dbench.py (python exp.py dbench.py CACHE DUMP BENCH_ARGS...); see the README's 'Tried' section."""
import os, runpy, sys
import torch
import torch.nn.functional as F
import sdn3d.editing.photo.transfer as tr
EXP = os.environ.get("EXP", "")
orig = tr._part_examples
def interior(src, s_mesh):
    m = (src.frags.pix_to_mesh[0] == s_mesh).float()[None, None]
    return (-F.max_pool2d(-m, 3, 1, 1))[0, 0].bool().view(-1)
def pe(b, s_mesh, visible_px, before, src, parts_src, img_flat, settings):
    if EXP == "interior" and len(visible_px):
        keep = interior(src, s_mesh)[visible_px]
        if int(keep.sum()) >= 16:
            found, _ = orig(b, s_mesh, visible_px[keep], before, src, parts_src, img_flat, settings)
            return found, img_flat[visible_px].double()
    return orig(b, s_mesh, visible_px, before, src, parts_src, img_flat, settings)
tr._part_examples = pe
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
