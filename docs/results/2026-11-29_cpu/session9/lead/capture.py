# ruff: noqa
"""capture.py SPEC OUT PT: run one real-frame edit and save removal_vanishing_point's and ray_fill's inputs."""
import sys, torch
import sdn3d.editing.photo.road as R
import sdn3d.editing.photo.transfer as T
import sdn3d.editing.photo.fill as FL
got = {}
o_rvp = R.removal_vanishing_point
def rvp(image, K, removed, objects_px, ry=None):
    out = o_rvp(image, K, removed, objects_px, ry)
    got.update(image=image.clone(), K=K.clone(), removed=removed.clone(), objects_px=objects_px.clone(), ry=ry, vp=out)
    return out
T.removal_vanishing_point = rvp
o_rf = R.ray_fill
def rf(image, hole, vp, keep_out=None, *a, **k):
    got.update(rf_image=image.clone(), rf_hole=hole.clone(), rf_keep=None if keep_out is None else keep_out.clone(), rf_a=a, rf_kw=k, rf_vp=vp)
    return o_rf(image, hole, vp, keep_out, *a, **k)
R.ray_fill = rf
import sdn3d.editing.photo.fill as FL
if hasattr(FL, "ray_fill"): FL.ray_fill = rf
o_rwe = T._rays_with_effects
def rwe(image, hole, objects_px, search, ring, road, settings, vanishing):
    got.update(rwe_image=image.clone(), rwe_hole=hole.clone(), rwe_objects=objects_px.clone(), rwe_search=search.clone(), rwe_ring=ring.clone(), rwe_road=road.clone(), rwe_settings=settings)
    return o_rwe(image, hole, objects_px, search, ring, road, settings, vanishing)
T._rays_with_effects = rwe
from sdn3d.cli.edit import main
rc = main([f"input.image=/work/main/tests/data/0006_30-deg-right_00043.png", "run=/tmp/s5data/lead/demo/runs", "proposals=boxes",
           f"edits={sys.argv[1]}", f"output_dir={sys.argv[2]}", "overwrite=true"])
torch.save(got, sys.argv[3])
print("rc", rc, "vp", got.get("vp"), "rf_vp", got.get("rf_vp"), {k: v for k, v in got.get("rf_kw", {}).items()})
