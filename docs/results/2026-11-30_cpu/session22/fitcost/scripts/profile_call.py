"""cProfile of one ``sdn3d-edit`` call in this process (``main(argv)``, so the process is not ended early).

    cd WORKTREE && OMP_NUM_THREADS=1 PYTHONPATH=src python docs/results/2026-11-30_cpu/session22/fitcost/scripts/\
profile_call.py OUT.prof [TOP] -- <sdn3d-edit overrides>

Writes the profile to OUT.prof and prints the TOP (default 40) functions by own time and by cumulative time.
"""

from __future__ import annotations

import cProfile
import pstats
import sys


def main() -> None:
    split = sys.argv.index("--")
    head, overrides = sys.argv[1:split], sys.argv[split + 1:]
    out, top = head[0], int(head[1]) if len(head) > 1 else 40
    profiler = cProfile.Profile()
    profiler.enable()
    from sdn3d.cli.edit import main as edit_main

    code = edit_main(overrides)
    profiler.disable()
    profiler.dump_stats(out)
    stats = pstats.Stats(out)
    stats.sort_stats("tottime").print_stats(top)
    stats.sort_stats("cumulative").print_stats(top)
    print("exit", code)


if __name__ == "__main__":
    main()
