# ruff: noqa: E402, E501, E701, E702
"""lab_layout_check.py: is the photo path's Lab conversion (sdn3d.editing.photo.recolor.srgb_to_lab, kornia's
operations) independent of the layout of the pixels it converts? It would have to be for one conversion per picture
region to replace the separate ones of shadowed_road, road_haze and _matched_weight bit for bit.

1. torch.pow(x, e) of float32 on every float in the ranges srgb_to_lab raises to 2.4 and 1/3: the vectorised path (a
   long contiguous tensor) against the scalar path (a strided view, as the last elements of a contiguous tensor
   that do not fill a vector take).
2. srgb_to_lab of pixel ranges x[s:s + n] against the same pixels in the conversion of the whole x."""
import time

import torch

torch.set_num_threads(1)
from sdn3d.editing.photo.recolor import srgb_to_lab

print("torch", torch.__version__, "CPU capability", torch.backends.cpu.get_cpu_capability())


def all_floats(lo, hi):
    a = torch.tensor([lo], dtype=torch.float32).view(torch.int32).item()
    b = torch.tensor([hi], dtype=torch.float32).view(torch.int32).item()
    return torch.arange(a, b + 1, dtype=torch.int32).view(torch.float32)


for name, lo, hi, e in [("linearise: pow(x, 2.4)", (0.04045 + 0.055) / 1.055, 1.0, 2.4),
                        ("Lab f: pow(x, 1/3)", 0.008856, 1.2, 1 / 3.0)]:
    x = all_floats(lo, hi)
    t = time.time()
    vec = torch.pow(x, e)
    y = torch.stack([x, x], 1).reshape(-1)[::2]  # the same floats, stride 2: the scalar loop
    sca = torch.pow(y, e)
    d = vec != sca
    print(f"{name}: {len(x)} floats in [{lo:.6f}, {hi}], vector and scalar paths differ on {int(d.sum())} "
          f"({100 * float(d.float().mean()):.1f} %), e.g. x = {x[d][0].item():.9g}: {vec[d][0].item():.9g} vs {sca[d][0].item():.9g}")

g = torch.Generator().manual_seed(0)
x = torch.rand(100000, 3, generator=g)
full = srgb_to_lab(x)
cases = bad = 0
for n in [1, 5, 16, 17, 100, 1001, 5003, 99000]:
    for s in [0, 1, 7, 333]:
        sub = srgb_to_lab(x[s:s + n])
        d = (sub != full[s:s + n]).any(1)
        cases += 1
        bad += int(d.any())
        if d.any():
            where = d.nonzero().flatten()
            print(f"  pixels {s}..{s + n - 1} converted alone: {int(d.sum())} differ from the whole conversion, at "
                  f"positions {where.tolist()[:6]} of {n} (the last pixels: the scalar tail)")
print(f"{bad} of {cases} ranges differ in some pixel: the conversion depends on the layout, not bit-identical")
