# ruff: noqa: B023, E501, E702, E731
"""predsize.py DIAG.json ...: how good the sizes are that the fit's size priors pull towards (diag.py's records; the
truth an oracle, for scoring only): per file, mean |log| error of (l, h, w) of the geometric branch's predicted size
(the centre of dims_reg), of each car's class mean of the true sizes (a constant per class, an oracle), of the truth
template's own size (TEMPLATE_DIMENSIONS) and of the fitted winner's size; the correlation of predicted and true
lengths; the fitted size's mean log ratio to the truth."""
import json
import sys

import numpy as np

from sdn3d.meshes.templates import TEMPLATE_DIMENSIONS, TEMPLATE_NAMES

for f in sys.argv[1:]:
    c = json.load(open(f))
    t = np.log([x["truth_dims"] for x in c]); p = np.log([x["pred_dims"] for x in c])
    tt = np.log([TEMPLATE_DIMENSIONS[TEMPLATE_NAMES[x["truth_tpl"]]] for x in c])
    fw = np.log([x["hyps"][x["win"]]["dims"] for x in c])
    cls = np.array([x["class"] for x in c])
    cm = np.stack([t[cls == k].mean(0) for k in cls])
    err = lambda a: np.abs(a - t).mean(0).round(3).tolist()
    print(f"{f.split('/')[-1]}: {len(c)} cars; |log| error (l, h, w): predicted {err(p)}, class mean of the truth {err(cm)}, "
          f"truth template's own size {err(tt)}, fitted {err(fw)}; corr(predicted, true length) {np.corrcoef(p[:, 0], t[:, 0])[0, 1]:.2f}; "
          f"fitted / true, mean log ratio {(fw - t).mean(0).round(3).tolist()}")
