# ruff: noqa: E402
"""A CPU-time cProfile of session 14's draw_edits.py (its arguments follow, ``--profile`` included): the profiler's
clock is the process's CPU time (time.process_time), so other processes on a shared machine inflate it far less
than the wall clock. Run from the repository root with PYTHONPATH=CODE/src:

    python profile_cpu.py TREE OUT --profile --only 0,1,3,6,10,11
"""

import cProfile
import runpy
import sys
import time

DRAW_EDITS = "docs/results/2026-11-29_cpu/session14/cost/draw_edits.py"
_Profile = cProfile.Profile


class CpuProfile(_Profile):
    def __init__(self, *args, **kwargs):
        super().__init__(time.process_time, *args, **kwargs)


cProfile.Profile = CpuProfile
sys.argv = [DRAW_EDITS, *sys.argv[1:]]
runpy.run_path(DRAW_EDITS, run_name="__main__")
