"""Decoding one Virtual KITTI 1.3.1 frame's annotations at the native 1242x375 with ``vkitti1.load_instances``; prints
JSON.

    python benchmarks/decode_frame.py [--runs 5]

Writes, in a temporary directory, one frame of the reference layout (:func:`sdn3d.data.fixtures.write_vkitti1_fixture`,
world 0006, 30-deg-right, frame 43, 1242x375, its synthetic scenegt and colour encoding), then times
:func:`~sdn3d.data.vkitti1.load_instances` on it ``--runs`` times in this process (scenegt PNG read, colour decode
to class and track ids). Reported: each run's wall seconds, their median, the Python calls of one decode (cProfile),
the frame's pixel count, and the machine. The target a reader must keep is well under one second a frame (the
training data loaders decode every frame once per epoch); ``tests/test_data_vkitti1.py`` checks, load-independently,
that the decode makes no per-pixel Python calls.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import os
import platform
import pstats
import statistics
import tempfile
import time

from sdn3d.data.fixtures import write_vkitti1_fixture
from sdn3d.data.vkitti1 import load_instances, read_frames


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5, help="timed decodes (default 5)")
    args = parser.parse_args()
    if args.runs < 1:
        parser.error(f"--runs must be at least 1, got {args.runs}")
    with tempfile.TemporaryDirectory() as root:
        write_vkitti1_fixture(root, world="0006", variation="30-deg-right", frames=(43,), size=(1242, 375))
        (record,) = read_frames(root)
        seconds = []
        for _ in range(args.runs):
            start = time.perf_counter()
            load_instances(record)
            seconds.append(time.perf_counter() - start)
        profiler = cProfile.Profile()
        profiler.runcall(load_instances, record)
        calls = pstats.Stats(profiler).total_calls
    print(json.dumps({
        "what": "vkitti1.load_instances on one 1242x375 frame (scenegt PNG read + colour decode), wall seconds",
        "runs_s": [round(s, 4) for s in seconds],
        "median_s": round(statistics.median(seconds), 4),
        "python_calls_per_decode": calls,
        "pixels": 1242 * 375,
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(), "load_average": os.getloadavg()},
    }, indent=2))


if __name__ == "__main__":
    main()
