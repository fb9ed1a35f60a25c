# ruff: noqa: E402, E501, E701, E702
"""facets.py: hooks that measure facets on a photo appearance's never-seen surfaces (imported by diag_real.py and
diag_cf.py). install() wraps transfer._draw (recording the template face each drawn pixel shows, from its target
rasterization) and appearance.render_photo (the result's picture, source and part maps); steps() then gives, over the
4-neighbour pixel pairs of the last picture whose two pixels are both drawn from no photo pixel (codes part, default,
fallback), of the same object and the same part, and whose faces' normals lie within CREASE degrees (one smooth
panel of the template, not a roof edge): the mean |dRGB| x 255 across a face edge and within one face."""
import math

import numpy as np
import torch

from sdn3d.editing import appearance
from sdn3d.editing.photo import transfer
from sdn3d.editing.photo.settings import DEFAULT, FALLBACK, PART

CREASE = 40.0
last = {}


totals = [0.0, 0, 0.0, 0]


def install(accumulate: bool = False):
    """Wrap the functions; with ``accumulate`` every render_photo call's steps() are added to ``totals``."""
    orig_draw, orig_sp, orig_rp = transfer._draw, transfer._surface_points, appearance.render_photo

    def draw(*args, **kwargs):
        tgt = args[5]

        def sp(r, pix):
            out = orig_sp(r, pix)
            if r is tgt:
                where = r.frags.locate(pix)
                f = r.frags.face_at(where)
                m = r.frags.mesh_at(where)
                tri = out[4]
                n = torch.nn.functional.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1), dim=-1)
                last["draw"] = (pix.clone(), f.clone(), m.clone(), n.clone())
            return out
        transfer._surface_points = sp
        try:
            return orig_draw(*args, **kwargs)
        finally:
            transfer._surface_points = orig_sp

    def render_photo(*args, **kwargs):
        last.pop("draw", None)
        result = orig_rp(*args, **kwargs)
        last["result"] = result
        if accumulate:
            for i, v in enumerate(steps()):
                totals[i] += v
        return result
    transfer._draw = draw
    appearance.render_photo = render_photo


def steps(only_mesh: int | None = None):
    """(sum across, n across, sum within, n within) for the last render_photo call (zeros without a draw); with
    ``only_mesh`` the pairs of that drawn mesh alone (session 29)."""
    if "draw" not in last:
        return 0.0, 0, 0.0, 0
    res = last["result"]
    pix, f, m, n = last["draw"]
    img = res.image.double().permute(1, 2, 0).numpy() * (255.0 if res.image.is_floating_point() else 1.0)
    h, w, _ = img.shape
    codes = res.source.numpy().reshape(-1)
    parts = res.parts.numpy().reshape(-1) if res.parts is not None else np.zeros(h * w)
    face = np.full(h * w, -1)
    face[pix.numpy()] = f.numpy()
    mesh = np.full(h * w, -1)
    mesh[pix.numpy()] = m.numpy()
    normal = np.zeros((h * w, 3))
    # the camera-facing face normal; a face's pixels share it up to sign: compare |cos|
    normal[pix.numpy()] = n.numpy()
    new = np.isin(codes, [PART, DEFAULT, FALLBACK]) & (face >= 0)
    if only_mesh is not None:
        new &= mesh == only_mesh
    cos = math.cos(math.radians(CREASE))
    out = [0.0, 0, 0.0, 0]
    F2, M2, P2, NEW = (x.reshape(h, w) for x in (face, mesh, parts, new))
    N2, IM = normal.reshape(h, w, 3), img
    for a, b in (((slice(None), slice(0, -1)), (slice(None), slice(1, None))), ((slice(0, -1), slice(None)), (slice(1, None), slice(None)))):
        ok = NEW[a] & NEW[b] & (M2[a] == M2[b]) & (P2[a] == P2[b]) & (np.abs((N2[a] * N2[b]).sum(-1)) >= cos)
        d = np.abs(IM[a] - IM[b]).mean(-1)[ok]
        same = (F2[a] == F2[b])[ok]
        out[0] += float(d[~same].sum())
        out[1] += int((~same).sum())
        out[2] += float(d[same].sum())
        out[3] += int(same.sum())
    return tuple(out)
