# ruff: noqa: E402, E501
"""dcache.py CACHE_DIR BENCH_ARGS...: only the de-render of every source frame of a Table 1 tree, cached exactly as
dbench.py caches it (same key, same models and settings, the bench's own _source_scene), no edit evaluated. Then
fit_cues.py / census.py read the cache, and a later dbench.py run with the same cache reuses the scenes
(session 28 merge40)."""
import sys
import time

sys.argv = [sys.argv[0], sys.argv[1], sys.argv[1] + ".nodump", *sys.argv[2:]]
import dbench  # noqa: F401  (installs the cache on eb._source_scene; its main is not run on import)

import sdn3d.evaluation.edit_benchmark as eb
from sdn3d.data.frames import load_frame

SEEN = set()


def evaluate_entry(index, entry, source, target, models, settings, *a, **k):
    key = (source.world, source.variation, source.frame)
    if key not in SEEN:
        SEEN.add(key)
        t = time.perf_counter()
        src = load_frame(source, settings.image_size, semantic=False, instances=False)
        dbench.cached(src.image, src.intrinsics, source, models, settings)
        print(f"derendered {key} {time.perf_counter() - t:.1f}s", flush=True)
    return eb.EntryResult(index, "skipped", 0, errors={"entry": "skipped (dcache)"})


eb.evaluate_entry = evaluate_entry
from sdn3d.cli.bench import main

sys.exit(main(sys.argv[3:]))
