# ruff: noqa: INP001
"""nobelow.py SCRIPT ARGS...: runs SCRIPT with the band under the semantic proposals that the fit ignores
(proposal_fit.UNSURE_BELOW, 0.3 of a mask's height) set to UNSURE_BELOW_SET (0: none). For tuning, session 37."""
import os
import runpy
import sys

import sdn3d.proposal_fit as pf

pf.UNSURE_BELOW = float(os.environ["UNSURE_BELOW_SET"])
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
