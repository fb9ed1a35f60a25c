# ruff: noqa: E402, E501, E701, E702
"""belt.py: the belt line's sharpness on a turned car's never-seen side (session 30 gouraud30; imported by
diag_real.py after facets.install() and a render). Over the last picture's vertical 4-neighbour pixel pairs of one drawn
mesh whose upper pixel is the template's GLASS (result.parts, the greenhouse's glass included) and the lower BODY, both
drawn from no photo pixel (codes part, another car, default, fallback): the projected glass/body boundary, one pair a
column. Per column the luma (Rec. 601, 0-255) of the body pixel just below minus that of the glass pixel just above
(`step`, the belt line's step at 1 px), and the same of the pixels 4 rows farther out (`contrast4`: body at +5, glass
at -4, both still of their part and never seen). Reported: the columns n, mean |step| (**the belt-line sharpness
number**: a crisp window line has its whole contrast in one pixel step; a fade spreads it over rows and leaves little
step), mean contrast4, and their ratio mean|step| / mean|contrast4| (1: all contrast at the line)."""
import numpy as np

from sdn3d.editing.photo.settings import ANOTHER_CAR, DEFAULT, FALLBACK, PART
from sdn3d.meshes.parts import Part

OUT_ROWS = 4


def belt(res, pix, m, mesh):
    img = res.image.double().permute(1, 2, 0).numpy() * (255.0 if res.image.is_floating_point() else 1.0)
    h, w, _ = img.shape
    luma = img @ np.array([0.299, 0.587, 0.114])
    codes = res.source.numpy().reshape(h, w)
    parts = res.parts.numpy().reshape(h, w).astype(int)
    mine = np.zeros(h * w, bool)
    mine[pix[m == mesh].numpy()] = True
    new = mine.reshape(h, w) & np.isin(codes, [PART, ANOTHER_CAR, DEFAULT, FALLBACK])
    glass = new & (parts == int(Part.GLASS))
    body = new & (parts == int(Part.BODY))
    steps, far = [], []
    for x in range(w):
        ys = np.nonzero(glass[:-1, x] & body[1:, x])[0]
        for y in ys[:1]:  # the first glass-over-body pair from the top: the belt line
            steps.append(luma[y + 1, x] - luma[y, x])
            lo, hi = y - OUT_ROWS, y + 1 + OUT_ROWS
            if lo >= 0 and hi < h and glass[lo:y + 1, x].all() and body[y + 1:hi + 1, x].all():
                far.append(luma[hi, x] - luma[lo, x])
    s, f = np.abs(np.array(steps)), np.abs(np.array(far))
    return {"columns": len(s), "sharpness: mean |luma step| at the belt line": round(float(s.mean()), 2) if len(s) else None,
            "mean signed step (body - glass)": round(float(np.mean(steps)), 2) if len(s) else None,
            "columns with +-4 rows": len(f), "mean |luma contrast| +-4 rows": round(float(f.mean()), 2) if len(f) else None,
            "step / contrast": round(float(s.mean() / max(f.mean(), 1e-9)), 3) if len(f) and len(s) else None}
