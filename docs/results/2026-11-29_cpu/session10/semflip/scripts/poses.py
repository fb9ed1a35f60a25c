# ruff: noqa: E402, E501, E701, E702
"""poses.py DIAG.json...: the poses the edit path used for Table 1's rotate entries (every modify op's picked object
against the truth; ops repeat a car across entries): per variation, median yaw error, flips over 90 degrees,
template accuracy, median relative distance error, median fit IoU."""
import json
import sys

import numpy as np

for f in sys.argv[1:]:
    ops = [(r["key"].split()[0].split("/")[1], o) for r in json.load(open(f)) for o in r["ops"] if "yaw_err" in o]
    for var in sorted({v for v, _ in ops}):
        oo = [o for v, o in ops if v == var]
        fits = [o["fit"]["fit_iou"] for o in oo if o.get("fit") and o["fit"]["fit_iou"] is not None]
        print(f"{f.split('/')[-1]:24s} {var:6s} ops {len(oo):3d} median yaw err {np.median([o['yaw_err'] for o in oo]):6.1f} flips {sum(o['flip'] for o in oo):3d} ({100 * np.mean([o['flip'] for o in oo]):4.1f} %) template {100 * np.mean([o['tpl_true'] == o['tpl_fit'] for o in oo]):4.1f} % median z err {np.median([o['z_err'] for o in oo]):+.3f} median fit IoU {np.median(fits) if fits else float('nan'):.3f} median mask IoU {np.median([o['mask_iou'] for o in oo]):.3f}")
