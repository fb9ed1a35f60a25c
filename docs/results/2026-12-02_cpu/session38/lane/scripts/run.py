"""Experiment runner: stash each derender's image for the fit's lane prior, then run a script or module.
usage: run.py (-m module | script.py) args...   env LANE_MODE=image|oracle|off, LANE_SCOPE=local|global"""
import runpy, sys, math
import sdn3d.derender as D
import sdn3d.geometric.fit as F
_orig = D.derender
def wrapped(image, intrinsics, *a, **k):
    F.EXPERIMENT_IMAGE[:] = [image]
    gt = k.get("ground_truth")
    return _orig(image, intrinsics, *a, **k)
D.derender = wrapped
if sys.argv[1] == "-m":
    mod = sys.argv[2]; sys.argv = [mod] + sys.argv[3:]
    # patch modules that imported derender by name
    import importlib
    runpy.run_module(mod, run_name="__main__", alter_sys=True)
else:
    path = sys.argv[1]; sys.argv = sys.argv[1:]
    runpy.run_path(path, run_name="__main__")
