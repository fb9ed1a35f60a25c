# ruff: noqa
import sys, time, torch, numpy as np
torch.set_num_threads(1)
import sdn3d.geometric.fit as fit
import sdn3d.render.soft as soft
a = dict(torch.load(sys.argv[1], weights_only=False))
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
first = torch.where(torch.isfinite(a["start_ry"]), a["start_ry"], torch.full_like(a["start_ry"], -1.5708))
stats = {}
inner = soft._call
def call(kernel, direction, screen, box, fpm, settings, *out):
    t = time.thread_time()
    inner(kernel, direction, screen, box, fpm, settings, *out)
    dt = time.thread_time() - t
    b = box.numpy(); m = len(b) // fpm
    real = 0; walked = 0; nonempty = 0
    for i in range(m):
        bb = b[i*fpm:(i+1)*fpm]; w, h = bb[:, 2], bb[:, 3]; ok = (w > 0) & (h > 0)
        w, h = w[ok], h[ok]; nonempty += ok.sum()
        order = np.lexsort((w, h)); w, h = w[order], h[order]
        real += (w*h).sum()
        for g in range(0, len(w), 16):
            walked += 16 * w[g:g+16].max() * h[g:g+16].max()
    key = (direction, settings.image_size[0], fpm)
    s = stats.setdefault(key, [0, 0, 0, 0, 0.0, 0])
    s[0] += 1; s[1] += real; s[2] += walked; s[3] += m; s[4] += dt; s[5] += nonempty
soft._call = call
r = fit.fit_to_masks(masks, boxes, intr, yaw_belief=lambda ry: torch.cos(ry - first[:, None]), **a)
print("radius", soft.SoftSilhouetteSettings((64, 64), sigma=0.25).cull_radius)
for k, s in stats.items():
    print(k, "calls", s[0], "meshes", s[3], "nonempty faces/mesh", round(s[5]/s[3],1), "real pairs/mesh", round(s[1]/s[3]), "walked/real", round(s[2]/s[1], 2), "cpu", round(s[4], 2), "ns/walked pair", round(1e9*s[4]/s[2]*16, 2), "(per lane-vector)")
