# ruff: noqa: E402, E501, E701, E702
"""tune.py CBENCH ARGS...: cbench.py with proposal_fit.UNSURE_BELOW from the environment (UNSURE, tuning only)."""
import os
import runpy
import sys

if os.environ.get("UNSURE"):
    import sdn3d.proposal_fit as P
    P.UNSURE_BELOW = float(os.environ["UNSURE"])
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
