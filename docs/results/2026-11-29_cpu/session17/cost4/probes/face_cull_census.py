# ruff: noqa: B007, E401, E501, E702, E731, B023, I001
"""Probe (README section 4): of the (face, row) pairs of the captured latency rasterizations (a capture file of
rasterize arguments; made by a wrapper of transfer._rasterize), how many belong to faces without a pixel column in
their u range (an exact cull that was not made) and how many are empty."""
import sys, torch
from sdn3d.render._common import face_vertices, project_vertices, twice_area, AREA_EPS
from sdn3d.render.rasterize import _barycentric_planes, _row_spans
torch.set_num_threads(1)
cap = torch.load(sys.argv[1])
tot_pairs = tot_cullable = tot_zero = 0
for rows_, verts, faces, K, size in cap["calls"][::3]:
    height, width = size
    v = verts.double(); n = len(v)
    f = faces if faces.dim() == 3 else faces.expand(n, -1, -1)
    screen, ok = project_vertices(v, K.expand(n, 3, 3), 0.1)
    screen = face_vertices(screen, f).reshape(-1, 3, 2)
    valid = face_vertices(ok.unsqueeze(-1), f).reshape(-1, 3).all(-1)
    area2 = twice_area(screen); valid &= area2.abs() > AREA_EPS
    umin, umax = screen[..., 0].amin(1), screen[..., 0].amax(1)
    fr = torch.ceil(screen[..., 1].amin(1).clamp(-1.0, height)).clamp(min=0).long()
    lr = torch.floor(screen[..., 1].amax(1).clamp(-1.0, height)).clamp(max=height - 1).long()
    valid &= (umax >= 0) & (umin <= width - 1) & (lr >= fr)
    ids = valid.nonzero().flatten()
    rpf = lr[ids] - fr[ids] + 1
    nocol = torch.ceil(umin[ids] - 1e-6) > torch.floor(umax[ids] + 1e-6)
    a, b, c = _barycentric_planes(screen[ids], area2[ids])
    pf = torch.repeat_interleave(rpf)
    rs = torch.cumsum(rpf, 0) - rpf
    rows = fr[ids][pf] + torch.arange(len(pf)) - rs[pf]
    first, cols = _row_spans(a[pf], b[pf], c[pf], rows.double(), width)
    assert int(cols[nocol[pf]].sum()) == 0
    tot_pairs += len(pf); tot_cullable += int(nocol[pf].sum()); tot_zero += int((cols == 0).sum())
    print(len(ids), "faces", len(pf), "pairs", int(nocol[pf].sum()), "pairs of faces without a column", int((cols == 0).sum()), "empty pairs")
print("total pairs", tot_pairs, "cullable", tot_cullable, "empty", tot_zero)
