# ruff: noqa: INP001, E501, E401, E701, E702, B007, F401, I001
"""khat.py POSE.json[.gz] [DIMS]: per-frame camera-height estimate from the fitted cars' sizes against their templates' typical sizes."""
import gzip, json, sys
from collections import defaultdict
import numpy as np
from sdn3d.meshes.templates import TEMPLATE_DIMENSIONS
names = list(TEMPLATE_DIMENSIONS)
path = sys.argv[1]; which = [int(c) for c in (sys.argv[2] if len(sys.argv) > 2 else "12")]
d = json.load(gzip.open(path) if path.endswith('gz') else open(path))
for row, objs in d['objects'].items():
    m = [o for o in objs if o['matched'] and o['dist_signed'] is not None and o['center'] and np.isfinite(o['center'][1])]
    fr = defaultdict(list)
    for o in m: fr[o['frame']].append(o)
    before, after, shrink = [], [], []
    ests = []
    for f, os_ in fr.items():
        h = os_[0]['true_center'][1]; cam = os_[0]['center'][1]
        r = [np.mean([np.log(o['dims'][j] / TEMPLATE_DIMENSIONS[names[o['template']]][j]) for j in which]) for o in os_ if not o['truncated']] or [0.0]
        est = float(np.median(r))       # log(h0 / h_est): the fitted sizes are too large by this
        ests.append((np.log(cam / h), est, len(r)))
        for o in os_:
            s = o['dist_signed']
            before.append(abs(s)); after.append(abs(s - est))
            for a in (0.5,): shrink.append(abs(s - a * est))
    e = np.array(ests)
    print(f"{row}: frames {len(fr)}, cars {len(m)}; corr(true bias, est) {np.corrcoef(e[:,0], e[:,1])[0,1]:.2f}; slope {np.polyfit(e[:,0], e[:,1], 1)[0]:.2f}; "
          f"|dist| median before {np.median(before)*100:.1f} after full {np.median(after)*100:.1f} half {np.median(shrink)*100:.1f}; mean before {np.mean(before)*100:.1f} after {np.mean(after)*100:.1f}")
