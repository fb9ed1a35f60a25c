# ruff: noqa: INP001, E501, E401, E231, E702, E701, I001
"""angle.py TREE RUN...: rotate entries of a Table 1 photo row grouped by turn angle: 3D-SDN minus 2D, PSNR all."""
import json,math,sys,numpy as np
tree, *runs = sys.argv[1:]
ents=json.load(open(f'{tree}/vkitti_edit_benchmark.json'))
for run in runs:
    (recs,)=json.load(open(f'{run}/results.json'))['entries'].values()
    rows=[]
    for r in recs:
        if r['edit_kind']!='rotate': continue
        e=ents[r['index']]; op=e['operations'][0]
        ang=abs(math.degrees(float(op['ry']))); ang=min(ang,360-ang)
        m=r['metrics']['photo']
        rows.append((ang, m['3d-sdn']['all']['psnr']-m['2d']['all']['psnr'], float(op['zoom'])))
    a=np.array(rows)
    print(run, 'n', len(a))
    for lo,hi in ((0,30),(30,60),(60,120),(120,181)):
        s=a[(a[:,0]>=lo)&(a[:,0]<hi)]
        if len(s): print(f'  {lo}-{hi}: n {len(s)} gain {s[:,1].mean():+.2f} wins {(s[:,1]>0).sum()}')
