"""fit_iou_check.py: the proposals' fit records (meta['fits']: silhouette IoU, poor flag, hypothesis) of held-out
2227's car 12008 in 4 frames (clone/00029, which the branch un-flipped, and three it left flipped): a diagnosis after
the held-out measurement, deciding nothing. Run: OMP_NUM_THREADS=1 PYTHONPATH=CODE/src python fit_iou_check.py
(CODE: the branch's final code)."""
import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth
from sdn3d.data.sources import load_split
from sdn3d.derender import derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.models import Models, geometric_crop_settings

RUNS = "/tmp/s21data/demo/out/runs"
FRAMES = ("vkitti1/0001/clone/00029", "vkitti1/0001/clone/00036", "vkitti1/0001/clone/00057",
          "vkitti1/0001/rain/00038")
geo = f"{RUNS}/geometric/checkpoints/best-epoch009.ckpt"
crop = geometric_crop_settings(geo)
models = Models.from_checkpoints(geometric=geo, semantic=f"{RUNS}/semantic/checkpoints/best-epoch013.ckpt",
                                 **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
src = synth_data_source("/tmp/s24data/predflip/trees/t1_2227")
recs = {r.key: r for p in ("train", "val", "test") for r in load_split(src, p)}
torch.set_num_threads(1)
for key in FRAMES:
    r = recs[key]
    f = load_frame(r, (312, 96), semantic=False, instances=False)
    gt = ground_truth(r, (312, 96))
    sc = derender(f.image, f.intrinsics, models, "semantic", gt, fit=FitSettings(), photo=frame_photo(r, (312, 96)))
    m = gt.instances == 12008
    o = sc.objects
    iou = (o.mask & m).flatten(1).sum(1) / (o.mask | m).flatten(1).sum(1)
    iid = int(o.instance_id[int(iou.argmax())])
    print(key, [x for x in sc.meta["fits"] if x["id"] == iid])
