# ruff: noqa: E402, E501, E701, E702
"""summ.py JSON...: one line per diag_real.py output: both cars' facet ratio, the red car's steps, the belt numbers, codes."""
import json
import sys

for p in sys.argv[1:]:
    t=open(p).read(); d=json.loads(t[t.index('\n{')+1:] if not t.startswith('{') else t)
    f=d['facet steps (one smooth panel, never-seen pixels)']; r=d['facet steps, mesh 0 alone']
    b=[v for k,v in d.items() if k.startswith('belt line, mesh 0')][0]
    print(p, 'ratio both', f['ratio'], '| red', r['across a face edge'], r['within a face'], r['ratio'], '| belt', b['sharpness: mean |luma step| at the belt line'], b['mean signed step (body - glass)'], b['mean |luma contrast| +-4 rows'], b['step / contrast'], b['columns'], '| codes', d['codes of the pixels the turned cars won']['mesh 0'].get('part'), d['codes of the pixels the turned cars won']['mesh 1'].get('photo'))
