# ruff: noqa: E402, E501, E701, E702, B007, F401, F841, B905
"""cached_bench plus one JSON line per photo result: its objects' info (no pixel lists). LOG env: the jsonl path."""
import json
import os
import sys

import sdn3d.editing.appearance as ap

log = open(os.environ["LOG"], "w")
orig = ap.render_photo
count = [0]


def wrapped(*a, **k):
    r = orig(*a, **k)
    log.write(json.dumps({"call": count[0], "objects": {str(i): {kk: vv for kk, vv in v.items() if not kk.startswith("_")
                                                                 and isinstance(vv, (int, float, str))}
                                                        for i, v in r.objects.items()}}) + "\n")
    log.flush()
    count[0] += 1
    return r


ap.render_photo = wrapped
exec(open("/tmp/s5data/lead/cached_bench.py").read())
