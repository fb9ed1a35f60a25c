"""cost_parts.py: scripts/cost.py (tree 35, the branch) with the re-reading (_lamps_on_fits, fitted_silhouettes) and
the refits (fit_proposals inside _refit_on_agreed_lamps) timed apart (CPU). Run: OMP_NUM_THREADS=1
PYTHONPATH=CODE/src python cost_parts.py (CODE: the branch's code)."""
import runpy
import sys
import time
from pathlib import Path

import sdn3d.derender as D

T = {"read": 0.0, "sil": 0.0, "refit": 0.0, "n_refit_calls": 0}
STATE = {"in_refit": False}
orig_read, orig_sil, orig_fit, orig_refit = (D._lamps_on_fits, D.fitted_silhouettes, D.fit_proposals,
                                             D._refit_on_agreed_lamps)


def timed(name, function):
    def call(*a, **k):
        t = time.process_time()
        result = function(*a, **k)
        T[name] += time.process_time() - t
        return result
    return call


def fit(*a, **k):
    t = time.process_time()
    result = orig_fit(*a, **k)
    if STATE["in_refit"]:
        T["refit"] += time.process_time() - t
        T["n_refit_calls"] += 1
    return result


def refit(*a, **k):
    STATE["in_refit"] = True
    try:
        return orig_refit(*a, **k)
    finally:
        STATE["in_refit"] = False


D._lamps_on_fits, D.fitted_silhouettes = timed("read", orig_read), timed("sil", orig_sil)
D.fit_proposals, D._refit_on_agreed_lamps = fit, refit
sys.argv = ["cost.py", "/tmp/s21data/trees/t1_35", "/tmp/s24data/predflip/cost_branch35b.json"]
runpy.run_path(str(Path(__file__).with_name("cost.py")), run_name="__main__")
print(T)
