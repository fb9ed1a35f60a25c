# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
import sys, json, torch, numpy as np
sys.path.insert(0, "/work/main/benchmarks")
from PIL import Image
from sdn3d.derender import derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.models import Models
from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth, scene_from_frame
from sdn3d.data.sources import load_split
import pose_table
W="/tmp/s34/demo/outputs/demo/runs"
models = Models.from_checkpoints(geometric=f"{W}/geometric/checkpoints/inference.pt", semantic=f"{W}/semantic/checkpoints/inference.pt")
tiles=[]
for tree, key, iid in [("/tmp/s34/t1_41","vkitti1/0001/rain/00002",12004),("/tmp/s34/t1_43","vkitti1/0002/clone/00060",12006),("/tmp/s34/t1_43","vkitti1/0002/clone/00017",12007),("/tmp/s34/t1_35","vkitti1/0001/clone/00029",12007)]:
    source = synth_data_source(tree)
    rec = [r for part in ("train","val","test") for r in load_split(source, part) if r.key == key][0]
    size=(312,96)
    frame = load_frame(rec, size, semantic=False, instances=False); gt = ground_truth(rec, size); truth = scene_from_frame(rec, size)
    scene = derender(frame.image, frame.intrinsics, models, "semantic", gt, fit=FitSettings())
    tm = truth.objects.mask[pose_table.row_of(truth, iid)].bool()
    o=scene.objects
    r=max(range(len(o.mask)), key=lambda r: float((o.mask[r].bool()&tm).sum())/max(1,float((o.mask[r].bool()|tm).sum())))
    pm=o.mask[r].bool()
    img=(frame.image.permute(1,2,0).numpy()*255).astype(np.uint8)
    ys,xs=np.nonzero((pm|tm).numpy()); y0,y1,x0,x1=max(0,ys.min()-4),min(96,ys.max()+5),max(0,xs.min()-4),min(312,xs.max()+5)
    a=img[y0:y1,x0:x1].copy(); b=a.copy()
    m1=pm.numpy()[y0:y1,x0:x1]; m2=tm.numpy()[y0:y1,x0:x1]
    b[m1 & ~m2]=[255,0,255]; b[m2 & ~m1]=[0,255,255]
    t=np.concatenate([a,b],1); s=max(1,int(160/t.shape[0]))
    tiles.append(np.kron(t,np.ones((s,s,1),dtype=np.uint8)))
H=max(t.shape[0] for t in tiles); Wd=max(t.shape[1] for t in tiles)
canvas=np.full((sum(t.shape[0]+10 for t in tiles),Wd,3),255,np.uint8); y=0
for t in tiles: canvas[y:y+t.shape[0],:t.shape[1]]=t; y+=t.shape[0]+10
Image.fromarray(canvas).save("/tmp/s34/viz.png")
