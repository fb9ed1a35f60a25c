"""How often one sdn3d-edit call reads the semantic run's config.yaml (``sdn3d.runs.trained_data``) and how long each
read takes: the call run in-process with that function wrapped; prints one line per read on stderr.

    OMP_NUM_THREADS=1 PYTHONPATH=TREE/src SDN3D_CONFIG_DIR=TREE/conf python count_reads.py <sdn3d-edit overrides>
"""

import sys
import time

import sdn3d.runs as runs

log = []


def wrap(mod, name):
    f = getattr(mod, name)

    def w(*a, **k):
        t = time.perf_counter()
        r = f(*a, **k)
        log.append((mod.__name__, name, str(a[0])[-60:] if a else "", round(time.perf_counter() - t, 4)))
        return r
    setattr(mod, name, w)


wrap(runs, "trained_data")
from sdn3d.cli import edit  # noqa: E402

try:
    edit.main(sys.argv[1:])
except SystemExit:
    pass
for x in log:
    print(x, file=sys.stderr)
