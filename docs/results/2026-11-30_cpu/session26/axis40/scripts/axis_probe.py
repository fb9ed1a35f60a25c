"""axis_probe.py CACHE DUMP OVERRIDES...: session 11 semrain's dbench.py with a spy on the test-time fit's choice
(``sdn3d.geometric.fit._choose``): prints, for every fitted object, the fine stage's hypotheses (fitted yaw in degrees,
loss, the appearance's belief) and the winner. Env YAW_REG: replaces ``FitSettings.yaw_reg`` in every fit (to see
whether the pull towards the prediction's yaw moves a hypothesis off its axis). Run as dbench.py, e.g. with ONLY=39."""
import dataclasses
import math
import os
import runpy
import sys

import sdn3d.geometric.fit as gf

_choose, _fit = gf._choose, gf.fit_to_masks


def spy_choose(loss, belief, ry, settings):
    index = _choose(loss, belief, ry, settings)
    for i in range(loss.shape[0]):
        hyps = ", ".join(f"{math.degrees(float(ry[i, h])):+.1f}/{float(loss[i, h]):.4f}/{float(belief[i, h]):+.2f}"
                         for h in range(loss.shape[1]))
        print(f"object {i}: winner {int(index[i])} (ry/loss/belief: {hyps})", flush=True)
    return index


def fit(*a, **k):
    if os.environ.get("YAW_REG") is not None:
        k["settings"] = dataclasses.replace(k.get("settings") or gf.FitSettings(), yaw_reg=float(os.environ["YAW_REG"]))
    return _fit(*a, **k)


gf._choose = spy_choose
gf.fit_to_masks = fit
sys.argv = ["dbench.py", *sys.argv[1:]]
runpy.run_path("/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py", run_name="__main__")
