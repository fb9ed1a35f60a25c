# ruff: noqa: INP001, E501, E401, E701, E702, B007, F401, I001
"""sdist.py POSE.json.gz...: signed distance error against the frame's camera height (true_center[1]), per row."""
import gzip, json, sys, math
import numpy as np
from sdn3d.meshes.templates import TEMPLATE_DIMENSIONS
names = list(TEMPLATE_DIMENSIONS)
for path in sys.argv[1:]:
    d = json.load(gzip.open(path) if path.endswith('gz') else open(path))
    for row, objs in d['objects'].items():
        m = [o for o in objs if o['matched'] and o['dist_signed'] is not None]
        s = np.array([o['dist_signed'] for o in m]); h = np.array([o['true_center'][1] for o in m])
        cam = np.array([o['center'][1] for o in m])
        expect = np.log(cam / h)   # the bias a wrong camera height alone makes
        print(f"{path.split('/')[-1]} | {row}: n={len(m)} signed median {np.median(s)*100:+.1f} mean {s.mean()*100:+.1f} |abs| median {np.median(abs(s))*100:.1f}; "
              f"camera-height bias median {np.median(expect)*100:+.1f}; after removing it: signed median {np.median(s-expect)*100:+.1f} |abs| median {np.median(abs(s-expect))*100:.1f}")
        # size ratio: fitted dims / true dims (h, w), and fitted / template typical
        fd = np.array([o['dims'] for o in m]); td = np.array([o['true_dims'] for o in m])
        typ = np.array([TEMPLATE_DIMENSIONS[names[o['template']]] for o in m])
        r_true = np.log(fd / td); r_typ = np.log(fd / typ)
        print(f"   log fitted/true dims (l,h,w) median {np.round(np.median(r_true,0)*100,1)}; log fitted/template-typical {np.round(np.median(r_typ,0)*100,1)}; corr(signed dist, log h ratio)={np.corrcoef(s, r_true[:,1])[0,1]:.2f}")
