# ruff: noqa: E402, E501, E701, E702
"""Figure: the edited frame of one sdn3d-edit call (seed-31 tuning frame, 10 boxes, car 12005 turned by 30 degrees)
before (base f42d17c, threads 2) and after (this branch, threads 2: the fit in two groups on two threads, GrabCut beside
the semantic branch, no scipy), and their absolute difference."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from PIL import Image

before = np.asarray(Image.open(sys.argv[1]).convert("RGB")).astype(float) / 255
after = np.asarray(Image.open(sys.argv[2]).convert("RGB")).astype(float) / 255
diff = np.abs(after - before).max(2)
fig, ax = plt.subplots(3, 1, figsize=(8, 7.2))
ax[0].imshow(before); ax[0].set_title("before (base f42d17c, threads=2): edited.png")
ax[1].imshow(after); ax[1].set_title("after (this branch, threads=2: fit in 2 groups on 2 threads): edited.png")
im = ax[2].imshow(diff, cmap="magma", vmin=0, vmax=1); ax[2].set_title(f"|after - before|, max over RGB (pixels differing: {int((diff > 0).sum())})")
fig.colorbar(im, ax=ax[2], fraction=0.02)
for a in ax: a.set_xticks([]); a.set_yticks([])
fig.tight_layout(); fig.savefig(sys.argv[3], dpi=72)
