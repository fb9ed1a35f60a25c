"""cProfile of one ``sdn3d-edit`` call in this interpreter, imports included; writes a .prof and a text table.

    cd WORKTREE && OMP_NUM_THREADS=1 PYTHONPATH=CODE/src SDN3D_CONFIG_DIR=CODE/conf \
        python profile_call.py OUT_PREFIX IMAGE_624x192 SPEC RUN [threads]

The image must already be at the size wanted (``prep_image.py``); the call is ``sdn3d.cli.edit.main`` with
``input.image=IMAGE edits=SPEC run=RUN threads=N output_dir=OUT_PREFIX_out``. One untimed warm-up call first
(page cache), so that the profile sees a warm file cache as the benchmark's timed calls do.
"""

from __future__ import annotations

import cProfile
import io
import pstats
import shutil
import sys
import time
from pathlib import Path


def main() -> None:
    prefix, image, spec, run = sys.argv[1:5]
    threads = sys.argv[5] if len(sys.argv) > 5 else "2"
    out = Path(prefix + "_out")
    argv = [f"input.image={image}", f"edits={spec}", f"run={run}", f"threads={threads}", f"output_dir={out}",
            "overwrite=true"]
    profiler = cProfile.Profile()
    start = time.perf_counter()
    profiler.enable()
    import sdn3d.cli.edit as edit

    code = edit.main(argv)
    profiler.disable()
    wall = time.perf_counter() - start
    profiler.dump_stats(prefix + ".prof")
    text = io.StringIO()
    stats = pstats.Stats(profiler, stream=text).sort_stats("cumulative")
    stats.print_stats(120)
    Path(prefix + "_cumulative.txt").write_text(f"exit {code}, wall {wall:.3f} s under cProfile\n" + text.getvalue())
    text = io.StringIO()
    pstats.Stats(profiler, stream=text).sort_stats("tottime").print_stats(60)
    Path(prefix + "_tottime.txt").write_text(text.getvalue())
    shutil.rmtree(out, ignore_errors=True)


if __name__ == "__main__":
    main()
