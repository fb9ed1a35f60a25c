# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""picture_diff.py: pixels of the edited picture that changed between the code before the kernel and with it (both cars turned -90, smoothing on and off; /tmp/s33/nk/{before,after}_{true,false}/edited.png, written by side_by_side.sh)."""
import sys, numpy as np
from PIL import Image
for sm in ("true", "false"):
    a = np.asarray(Image.open(f"/tmp/s33/nk/sbs/before_{sm}/edited.png")).astype(int)
    b = np.asarray(Image.open(f"/tmp/s33/nk/sbs/after_{sm}/edited.png")).astype(int)
    d = np.abs(a - b).max(2)
    ch = d > 0
    print(f"smoothing={sm}: pixels changed {int(ch.sum())} of {ch.size} ({100*ch.mean():.4f} %), "
          f"mean max-channel change there {d[ch].mean() if ch.any() else 0:.2f}, largest {int(d.max())}, "
          f"changed by more than 8: {int((d > 8).sum())}")
