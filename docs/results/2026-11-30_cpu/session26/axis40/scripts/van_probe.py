"""van_probe.py CACHE DUMP OVERRIDES...: axis_probe.py (session 25 lead's: dbench.py with a spy on the fit's choice,
ONLY=entry) with one more spy on the street-axis refit (``fit._align_to_scene``, session 26): prints each fit's street
axes, the winners' yaws, and for the refitted rows the refit's yaw and loss against the winner's. Run as axis_probe.py
(PYTHONPATH=CODE/src:CODE, cd CODE, a fresh CACHE: a cached de-render fits nothing), e.g. ONLY=39 on spent tree 2241."""
import math
import runpy
import sys

import sdn3d.geometric.fit as gf

_align, _stage = gf._align_to_scene, gf._stage
IN_ALIGN = {"on": False}


def spy_stage(*a, **k):
    values, loss = _stage(*a, **k)
    if IN_ALIGN["on"]:
        print(f"refits: start {[f'{math.degrees(float(r)):+.1f}' for r in a[2]['ry']]} -> "
              f"{[f'{math.degrees(float(r)):+.1f}' for r in values['ry']]} loss {[round(float(v), 4) for v in loss]}",
              flush=True)
    return values, loss


def spy_align(choice, chosen, won, loss):
    IN_ALIGN["on"] = True
    try:
        out, new_loss, aligned = _align(choice, chosen, won, loss)
    finally:
        IN_ALIGN["on"] = False
    deg = [f"{math.degrees(float(a)):+.1f}" for a in choice.scene_axis]
    print(f"street axes {deg}; winners {[f'{math.degrees(float(r)):+.1f}' for r in chosen['ry']]} "
          f"loss {[round(float(v), 4) for v in loss]}; after {[f'{math.degrees(float(r)):+.1f}' for r in out['ry']]} "
          f"loss {[round(float(v), 4) for v in new_loss]} aligned {aligned.tolist()}", flush=True)
    return out, new_loss, aligned


gf._align_to_scene, gf._stage = spy_align, spy_stage
sys.argv = ["axis_probe.py", *sys.argv[1:]]
runpy.run_path(__file__.replace("van_probe.py", "axis_probe.py"), run_name="__main__")
