# ruff: noqa: E402, E501, E701, E702
"""tune.py CBENCH ARGS...: cbench.py with transfer.AIR_MIN_PIXELS from the environment (AIR_MIN, tuning only)."""
import os
import runpy
import sys

import sdn3d.editing.photo.transfer as T

if os.environ.get("AIR_MIN"):
    T.AIR_MIN_PIXELS = int(os.environ["AIR_MIN"])
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
