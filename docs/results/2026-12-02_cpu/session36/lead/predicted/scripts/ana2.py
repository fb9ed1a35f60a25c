# ruff: noqa: E401, E501, E701, E702, E731, I001
"""ana2.py SEMANTIC_RESULTS GT_RESULTS: Table 1 photo entries of one tree, 3D-SDN minus the 2D paste (PSNR all) on the
predicted row by how well the proposal the edit picked covers the target car (the 2D paste's layout IoU), with the
same entries' gain on ground-truth masks (an oracle) beside."""
import json, statistics as st, sys, random
def load(p, row):
    d = json.load(open(p)); return {e['key']: e for e in d['entries'][row] if 'photo' in e.get('metrics', {})}
S, G = load(sys.argv[1], 'semantic'), load(sys.argv[2], 'gt')
def ci(xs, n=2000):
    rnd = random.Random(0); ms = sorted(st.mean(rnd.choices(xs, k=len(xs))) for _ in range(n)); return ms[int(.025 * n)], ms[int(.975 * n)]
print("| kind | proposal IoU (2D layout) | entries | predicted: 3D-SDN - 2D, PSNR all [95 % bootstrap over entries] | 3D-SDN's layout IoU | same entries, GT masks: 3D-SDN - 2D |")
print("|---|---|---|---|---|---|")
for kind in ('rotate', 'zoom'):
    rows = []
    for k, e in S.items():
        m = e['metrics']['photo']; g = G.get(k, {}).get('metrics', {}).get('photo', {})
        if e['edit_kind'] != kind or '3d-sdn' not in m or '2d' not in m or '3d-sdn' not in g: continue
        rows.append((m['3d-sdn']['all']['psnr'] - m['2d']['all']['psnr'], m['3d-sdn']['layout']['mask_iou'], m['2d']['layout']['mask_iou'], g['3d-sdn']['all']['psnr'] - g['2d']['all']['psnr']))
    for lo, hi in ((0, .5), (.5, .7), (.7, 1.01), (0, 1.01)):
        sub = [r for r in rows if lo <= r[2] < hi]
        if len(sub) < 2: continue
        a, b = ci([r[0] for r in sub]); c, d = ci([r[3] for r in sub])
        name = 'all' if (lo, hi) == (0, 1.01) else f'[{lo}, {min(hi, 1)})'
        print(f"| {kind} | {name} | {len(sub)} | {st.mean(r[0] for r in sub):+.2f} [{a:+.2f}, {b:+.2f}] | {st.mean(r[1] for r in sub):.2f} | {st.mean(r[3] for r in sub):+.2f} [{c:+.2f}, {d:+.2f}] |")
