# ruff: noqa: E401, E402, E501, E701, E702, E731, I001, F401
import torch, numpy as np, time
torch.set_num_threads(1)
from sdn3d.editing.photo.recolor import srgb_to_lab, _RGB_TO_XYZ, _WHITE
M = (np.array(_RGB_TO_XYZ, np.float32) / np.array(_WHITE, np.float32)[:, None]).T.copy()
def lab_np(rgb):
    x = np.clip(rgb.float().numpy(), 0, 1)
    lin = np.where(x > 0.04045, np.power((x + np.float32(0.055)) / np.float32(1.055), np.float32(2.4)), x / np.float32(12.92))
    xyz = lin @ M
    f = np.where(xyz > np.float32(0.008856), np.cbrt(xyz), np.float32(7.787) * xyz + np.float32(4 / 29))
    out = np.empty_like(f)
    out[:, 0] = 116 * f[:, 1] - 16
    out[:, 1] = 500 * (f[:, 0] - f[:, 1])
    out[:, 2] = 200 * (f[:, 1] - f[:, 2])
    return torch.from_numpy(out)
g = torch.Generator().manual_seed(0)
x = torch.rand(438000, 3, generator=g)
x[:1000] = 0; x[1000:2000] = 1
a, b = srgb_to_lab(x), lab_np(x)
print("max abs Lab diff", (a - b).abs().max(0).values.tolist(), "ab-length diff", (a[:,1:].norm(dim=1)-b[:,1:].norm(dim=1)).abs().max().item())
def t(f, n=10):
    f(); s=time.process_time(); [f() for _ in range(n)]; return (time.process_time()-s)/n*1000
print("srgb_to_lab", t(lambda: srgb_to_lab(x)), "ms; numpy", t(lambda: lab_np(x)), "ms")
