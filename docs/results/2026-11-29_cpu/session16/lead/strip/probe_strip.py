# ruff: noqa: E402, E501, E702, I001, B905
import torch
import sdn3d.editing.photo.road as road
d = torch.load('/tmp/s16data/lead/strip/ray_inputs.pt', weights_only=False)
a, k = d['args'], d['kwargs']
image, hole, vp = a[0], a[1], a[2]
print('vp', vp, 'hole px', int(hole.sum()), 'ground_row', k.get('ground_row'), 'verge', k.get('verge'), 'road', k.get('road'))
rec = {}
orig = road._verge_near_only
def vno(c_out, c_in, both, rd):
    r = orig(c_out, c_in, both, rd)
    rec.setdefault('c_out', []).append(c_out.clone()); rec.setdefault('c_in', []).append(c_in.clone())
    rec.setdefault('both', []).append(both.clone()); rec.setdefault('far_only', []).append(r.clone())
    return r
road._verge_near_only = vno
out, reached = road.ray_fill(*a, **k)
c_out = torch.cat(rec['c_out'], 1); c_in = torch.cat(rec['c_in'], 1); both = torch.cat(rec['both']); fo = torch.cat(rec['far_only'])
ys, xs = hole.nonzero(as_tuple=True)
lab_out = road.road_lab(out[:, ys, xs].T.contiguous())
rd = k['road']
yellow = (lab_out[:, 2] - rd[2] > 8)
print('yellow hole px', int(yellow.sum()), 'of', len(ys))
vo = road.verge_like(c_out, rd); vi = road.verge_like(c_in, rd)
for name, m in [('yellow', yellow), ('all', torch.ones_like(yellow))]:
    print(name, 'n', int(m.sum()), 'both', int((both & m).sum()), 'near verge', int((vo & m).sum()), 'far verge', int((vi & m).sum()), 'far_only', int((fo & m).sum()))
m = yellow
print('yellow rows', int(ys[m].min()), int(ys[m].max()), 'cols', int(xs[m].min()), int(xs[m].max()))
lo = road.road_lab(c_out[:, m].T.contiguous()); li = road.road_lab(c_in[:, m].T.contiguous())
print('road lab', rd.tolist())
print('near-side lab median', lo.median(0).values.tolist(), 'far-side lab median', li.median(0).values.tolist())
import collections
print('cases (near verge, far verge, both):', collections.Counter(zip(vo[m].tolist(), vi[m].tolist(), both[m].tolist())))
