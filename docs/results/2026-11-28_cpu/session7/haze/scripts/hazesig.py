# ruff: noqa: E402, E501, E701, E702
"""Candidate fog signals for road_haze's inputs (session 7 haze diagnosis). install(log) wraps road.road_haze so that
every call appends a dict of signals (and the fit) to log."""
import math

import torch
import torch.nn.functional as F

import sdn3d.editing.photo.road as R
from sdn3d.image_ops import dilate_square


def luma(img):
    return 0.2126 * img[0] + 0.7152 * img[1] + 0.0722 * img[2]


def blur(x, s=1.5):
    r = int(3 * s); t = torch.arange(-r, r + 1).float(); g = torch.exp(-t ** 2 / (2 * s * s)); g = g / g.sum()
    y = F.conv2d(F.pad(x[None, None], (r, r, 0, 0), mode="replicate"), g.view(1, 1, 1, -1))
    return F.conv2d(F.pad(y, (0, 0, r, r), mode="replicate"), g.view(1, 1, -1, 1))[0, 0]


def signals(image, valid, hole, horizon):
    out = {}
    height, width = hole.shape
    ys, xs = hole.nonzero(as_tuple=True)
    extent = max(int(ys.max() - ys.min()), int(xs.max() - xs.min()), 20)
    rows = torch.arange(height, dtype=torch.float32)
    out["hole_rows"] = (int(ys.min()), int(ys.max())); out["horizon"] = horizon; out["H"] = height
    L = luma(image.float())
    hp = (L - blur(L, 1.5)).abs()
    # the picture around the horizon: contrast of a band of rows there vs the rows below it (fog flattens the far picture)
    h0 = int(round(horizon)); b = max(2, height // 24)
    band = slice(max(0, h0 - b), min(height, h0 + b + 1))
    low = slice(min(height - 1, h0 + 3 * b), height)
    vb = valid[band]; vl = valid[low]
    out["hz_hp"] = float(hp[band][vb].median()) if bool(vb.any()) else float("nan")
    out["low_hp"] = float(hp[low][vl].median()) if bool(vl.any()) else float("nan")
    out["hz_std"] = float(L[band][vb].std()) if int(vb.sum()) > 2 else float("nan")
    out["hz_rgb"] = image[:, band][:, vb].float().median(1).values.tolist() if bool(vb.any()) else None
    step = max(1, width // R.HAZE_COLUMNS)
    region = (dilate_square(hole, extent) & valid & (rows > horizon + 1)[:, None])[:, ::step]
    img = image[:, :, ::step]
    hpt = hp[:, ::step]
    road = R.road_colours(img, region)
    if road is None: out["fit"] = None; return out
    like = region & R.road_like(img, road, within=region)
    count = like.sum(1)
    use = (count >= R.HAZE_MIN_PIXELS).nonzero().flatten()
    if len(use) < R.HAZE_MIN_ROWS: out["fit"] = None; return out
    cols = like.any(0).nonzero().flatten()
    c0, c1 = int(cols[0]), int(cols[-1]) + 1
    bandi = img[:, use][:, :, c0:c1].float(); keep = like[use][:, c0:c1]
    med = torch.where(keep[None], bandi, torch.full_like(bandi, float("nan"))).nanmedian(2).values.double()
    con = torch.where(keep, hpt[use][:, c0:c1], torch.full_like(keep, float("nan"), dtype=torch.float32)).nanmedian(1).values.double()
    weight = count[use].double().sqrt()
    depth = (rows[use].double() - horizon).clamp(min=1.0)
    best, fit = math.inf, None
    flat = float((((med - (med * weight ** 2).sum(1, keepdim=True) / (weight ** 2).sum()) * weight) ** 2).sum())
    for k in R.HAZE_DEPTHS:
        x = torch.exp(-k / depth)
        design = torch.stack([torch.ones_like(x), x], 1) * weight[:, None]
        sol = torch.linalg.lstsq(design, (med * weight).T).solution
        err = float(((design @ sol - (med * weight).T) ** 2).sum())
        if err < best: best, fit = err, (k, sol)
    k, sol = fit
    x = torch.exp(-k / depth)
    out["fit"] = {"k": k, "fog": sol[0].tolist(), "delta": sol[1].tolist(), "refused": float(sol[1].mean()) > 0}
    out["r2"] = 1 - best / max(flat, 1e-12)
    out["rms"] = math.sqrt(best / float((weight ** 2).sum()) / 3)
    out["nrows"] = len(use); out["depth_range"] = (float(depth.min()), float(depth.max()))
    out["x_range"] = (float(x.min()), float(x.max()))
    # contrast vs transmission: fog multiplies the road's texture contrast by x
    ok = torch.isfinite(con) & (con > 1e-4)
    if int(ok.sum()) >= 4:
        lx, lc = torch.log(x[ok]), torch.log(con[ok]); w = weight[ok]
        A = torch.stack([torch.ones_like(lx), lx], 1) * w[:, None]
        s = torch.linalg.lstsq(A, (lc * w)[:, None]).solution
        out["con_slope"] = float(s[1])
        # slope of log contrast against log depth (minification alone also lowers contrast with distance)
        ld = torch.log(depth[ok]); A2 = torch.stack([torch.ones_like(ld), ld], 1) * w[:, None]
        out["con_vs_depth"] = float(torch.linalg.lstsq(A2, (lc * w)[:, None]).solution[1])
        n = int(ok.sum()); i = torch.argsort(depth[ok]); third = max(1, n // 3)
        out["con_far_near"] = float(con[ok][i[:third]].median() / con[ok][i[-third:]].median())
        out["x_far_near"] = float(x[ok][i[:third]].median() / x[ok][i[-third:]].median())
    below = (rows.double() - horizon).clamp(min=1.0)
    per_row = sol[0][:, None] + sol[1][:, None] * torch.exp(-k / below)[None]
    y0, y1 = out["hole_rows"]
    out["span"] = float((per_row[:, y0] - per_row[:, y1]).mean())
    out["med_span"] = float((med[:, 0] - med[:, -1]).mean())
    fogc = sol[0]
    out["fog_sat"] = float(fogc.max() - fogc.min())
    if out["hz_rgb"] is not None:
        out["fog_vs_hz"] = float((fogc - torch.tensor(out["hz_rgb"], dtype=torch.float64)).abs().max())
    return out


def install(log):
    orig = R.road_haze

    def wrapped(image, valid, hole, horizon, *a, **k):
        res = orig(image, valid, hole, horizon, *a, **k)
        try:
            s = signals(image, valid, hole, horizon)
        except Exception as e:  # diagnosis only
            s = {"error": repr(e)}
        s["applied"] = res is not None
        log.append(s)
        return res

    R.road_haze = wrapped
    return orig
