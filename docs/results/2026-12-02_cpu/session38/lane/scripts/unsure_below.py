# ruff: noqa: INP001, E501
"""unsure_below.py SCRIPT ARGS...: run SCRIPT with proposal_fit.UNSURE_BELOW set to env UB (session 38 lane prior)."""
import os
import runpy
import sys

import sdn3d.proposal_fit as P

P.UNSURE_BELOW = float(os.environ["UB"])
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
