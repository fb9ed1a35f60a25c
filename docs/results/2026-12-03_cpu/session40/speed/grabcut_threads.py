# ruff: noqa: INP001, E501
"""(For the reverted commit baa2e8cf, which added ``threads=``.) The two GrabCut passes of one ``sdn3d-edit`` call on their captured inputs (the pickled arguments of
``grabcut_masks`` and ``refine_with_silhouettes``, ``CAPTURE/gcm.pkl`` and ``CAPTURE/rws.pkl``), timed at one and two
threads (where the tree has ``threads=``), each result checked against the first call's.

    PYTHONPATH=<tree>/src python grabcut_threads.py CAPTURE [REPEATS]
"""

import inspect
import pickle
import sys
import time
from pathlib import Path

import torch

import sdn3d.box_masks as box_masks


def main() -> None:
    capture, repeats = Path(sys.argv[1]), int(sys.argv[2]) if len(sys.argv) > 2 else 4
    torch.set_num_threads(2)
    second_args, second_kwargs = pickle.loads((capture / "rws.pkl").read_bytes())
    first_args, first_kwargs = pickle.loads((capture / "gcm.pkl").read_bytes())
    pooled = "threads" in inspect.signature(box_masks.grabcut_masks).parameters
    again_ref = box_masks.refine_with_silhouettes(*second_args, **second_kwargs)
    first_ref = box_masks.grabcut_masks(*first_args, **first_kwargs)
    for _ in range(repeats):
        for threads in ([1, 2] if pooled else [1]):
            extra = {"threads": threads} if pooled else {}
            start, cpu = time.perf_counter(), time.process_time()
            again = box_masks.refine_with_silhouettes(*second_args, **second_kwargs, **extra)
            second_s, second_cpu = time.perf_counter() - start, time.process_time() - cpu
            start, cpu = time.perf_counter(), time.process_time()
            first = box_masks.grabcut_masks(*first_args, **first_kwargs, **extra)
            first_s, first_cpu = time.perf_counter() - start, time.process_time() - cpu
            same = torch.equal(first.masks, first_ref.masks) and torch.equal(first.from_box, first_ref.from_box)
            print(f"threads {threads}: second pass {second_s * 1000:.0f} ms (cpu {second_cpu * 1000:.0f}) same "
                  f"{torch.equal(again, again_ref)}; first pass {first_s * 1000:.0f} ms (cpu {first_cpu * 1000:.0f}) "
                  f"same {same}")


if __name__ == "__main__":
    main()
