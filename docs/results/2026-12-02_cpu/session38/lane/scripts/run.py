# ruff: noqa: INP001, E501
"""Experiment runner (session 38, with experiment.diff applied): hand each derender's image to the fit's lane
prior, then run a script or a module. usage: run.py (-m module | script.py) args...
Environment: LANE_MODE=image|off, LANE_SCOPE=local|global, LANE_REG, LANE_WIDTH, LANE_STARTS=1."""
import runpy
import sys

import sdn3d.derender as derendering
import sdn3d.geometric.fit as fitting

_original = derendering.derender


def _stashed(image, intrinsics, *args, **kwargs):
    fitting.EXPERIMENT_IMAGE[:] = [image]
    return _original(image, intrinsics, *args, **kwargs)


derendering.derender = _stashed  # before the benchmark's modules import it by name
if sys.argv[1] == "-m":
    module = sys.argv[2]
    sys.argv = [module, *sys.argv[3:]]
    runpy.run_module(module, run_name="__main__", alter_sys=True)
else:
    sys.argv = sys.argv[1:]
    runpy.run_path(sys.argv[0], run_name="__main__")
