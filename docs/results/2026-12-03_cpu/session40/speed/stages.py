# ruff: noqa: INP001, E501
"""Stage timer of one ``sdn3d-edit`` call: wraps its stage functions (ms per call, wall), runs ``main(argv)`` in this
process and prints the import and main times, then each stage's.

    PYTHONPATH=<tree>/src OMP_WAIT_POLICY=PASSIVE python stages.py input.image=... threads=2 run=... edits=... output_dir=...
"""

import functools
import importlib
import sys
import time

TIMES: dict[str, list[int]] = {}
STAGES = [("sdn3d.derender", "box_grabcut"), ("sdn3d.derender", "_semantics_and_instances"),
          ("sdn3d.derender", "add_box_objects"), ("sdn3d.derender", "_geometry"), ("sdn3d.derender", "_road_axes"),
          ("sdn3d.derender", "fit_proposals_and_boxes"), ("sdn3d.derender", "fit_proposals"),
          ("sdn3d.derender", "_choose_on_agreed_lamps"), ("sdn3d.derender", "fit_box_objects"),
          ("sdn3d.derender", "encode_scene"), ("sdn3d.derender", "_objects_3d"),
          ("sdn3d.box_objects", "_refine_box_masks"), ("sdn3d.derender", "derender"),
          ("sdn3d.cli.edit", "compose_config"), ("sdn3d.cli.edit", "load_models"), ("sdn3d.cli.edit", "_write_outputs")]


def wrap(module_name: str, name: str) -> None:
    module = importlib.import_module(module_name)
    fn = getattr(module, name)

    @functools.wraps(fn)
    def timed(*args, **kwargs):
        start = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            key = f"{module_name.split('.')[-1]}.{name}"
            TIMES.setdefault(key, []).append(round((time.perf_counter() - start) * 1000))

    setattr(module, name, timed)


def main() -> None:
    t0 = time.perf_counter()
    edit = importlib.import_module("sdn3d.cli.edit")
    t1 = time.perf_counter()
    for module_name, name in STAGES:
        wrap(module_name, name)
    try:
        edit.run_cli("edit", edit._main, sys.argv[1:])
    except SystemExit:
        pass
    t2 = time.perf_counter()
    print(f"import {1000 * (t1 - t0):.0f} main {1000 * (t2 - t1):.0f}")
    for key, values in TIMES.items():
        print(key, values)


if __name__ == "__main__":
    main()
