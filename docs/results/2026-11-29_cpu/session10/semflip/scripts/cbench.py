# ruff: noqa: E402, E501, E701, E702
"""sdn3d-bench with the de-rendered source scenes cached on disk (tuning only: a photo-path change keeps the
de-render; a fit change needs a fresh cache dir) and 3D-SDN's picked instance ids logged per entry.
python cbench.py CACHE_DIR PICKS_OUT.json BENCH_ARGS..."""
import hashlib
import json
import os
import sys

import torch

import sdn3d.evaluation.edit_benchmark as eb

cache, picks_out = sys.argv[1], sys.argv[2]
os.makedirs(cache, exist_ok=True)
original = eb._source_scene
PICKS = {}
STATE = {"entry": None}


def cached(image, intrinsics, record, models, settings):
    key = f"{record.world}_{record.variation}_{record.frame}_{settings.scene}_{settings.proposals}_{settings.fit}"
    path = os.path.join(cache, hashlib.md5(key.encode()).hexdigest() + ".pt")
    if os.path.exists(path):
        try:
            return torch.load(path, weights_only=False)
        except (RuntimeError, EOFError, OSError):
            pass
    scene = original(image, intrinsics, record, models, settings)
    tmp = f"{path}.{os.getpid()}.tmp"
    torch.save(scene, tmp)
    os.replace(tmp, path)
    with open(os.path.join(cache, "keys.txt"), "a") as f: f.write(f"{key} {os.path.basename(path)}\n")
    return scene


orig_eval, orig_mp = eb.evaluate_entry, eb._method_pictures


def evaluate_entry(index, entry, *a, **k):
    STATE["entry"] = index
    return orig_eval(index, entry, *a, **k)


def method_pictures(*a, **k):
    out = orig_mp(*a, **k)
    PICKS[STATE["entry"]] = out[3]
    return out


OBJS = {}
import numpy as np

import sdn3d.editing.appearance as ap

orig_rp = ap.render_photo


def render_photo(*a, **k):
    r = orig_rp(*a, **k)
    OBJS.setdefault(STATE["entry"], []).append({str(i): {kk: v for kk, v in o.items() if not kk.startswith("_")} for i, o in r.objects.items()})
    if os.environ.get("SAVEMAP"):
        np.save(f"{os.environ['SAVEMAP']}_{STATE['entry']}.npy", r.source.numpy())
    return r


ap.render_photo = render_photo
eb._source_scene = cached
eb.evaluate_entry = evaluate_entry
eb._method_pictures = method_pictures
from sdn3d.cli.bench import main

rc = main(sys.argv[3:])
json.dump({k: {"picks": v, "objects": OBJS.get(k)} for k, v in PICKS.items()}, open(picks_out, "w"))
sys.exit(rc)
