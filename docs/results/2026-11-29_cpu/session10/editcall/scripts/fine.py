# ruff: noqa: E402, E501, E701, E702
"""fine.py OUT.json -- overrides: benchmarks/edit_cost.py's phases plus the steps of run_edit around them (CPU, wall)."""
import functools
import importlib
import json
import sys
import time

T0 = time.perf_counter()
sys.argv = [sys.argv[0]] + sys.argv[1:]
out = sys.argv[1]; args = sys.argv[3:]
import sdn3d.cli.edit as edit

startup = time.process_time()
times = {}
def wrap(module, attribute):
    owner = importlib.import_module(module)
    *path, name = attribute.split(".")
    for p in path: owner = getattr(owner, p)
    inner = getattr(owner, name)
    @functools.wraps(inner)
    def timed(*a, **k):
        c, w = time.process_time(), time.perf_counter()
        try: return inner(*a, **k)
        finally:
            e = times.setdefault(f"{module}.{attribute}", [0.0, 0.0, 0]); e[0] += time.process_time() - c; e[1] += time.perf_counter() - w; e[2] += 1
    setattr(owner, name, timed)
for m, a in [("sdn3d.cli.edit", "compose_config"), ("sdn3d.cli.edit", "run_edit"), ("sdn3d.cli.edit", "_read_inputs"), ("sdn3d.cli.edit", "open_input"), ("sdn3d.cli.edit", "resolve_checkpoints"),
             ("sdn3d.cli.edit", "load_models"), ("sdn3d.cli.edit", "session_settings"), ("sdn3d.editing.session", "EditSession.derender"),
             ("sdn3d.derender", "_semantics_and_instances"), ("sdn3d.derender", "add_box_objects"), ("sdn3d.derender", "_geometry"),
             ("sdn3d.derender", "fit_proposals_and_boxes"), ("sdn3d.derender", "fit_box_objects"), ("sdn3d.box_masks", "refine_with_silhouettes"), ("sdn3d.derender", "encode_scene"),
             ("sdn3d.cli.edit", "trust_warnings"), ("sdn3d.editing.session", "EditSession.edit"), ("sdn3d.cli.edit", "config_record"), ("sdn3d.cli.edit", "_write_outputs")]:
    try: wrap(m, a)
    except Exception as exc: print("skip", m, a, exc, file=sys.stderr)
code = edit.main(args)
res = {"startup_cpu": round(startup, 3), "process_cpu": round(time.process_time(), 3), "process_wall": round(time.perf_counter() - T0, 3),
       "phases": {k: [round(v[0], 3), round(v[1], 3), v[2]] for k, v in times.items()}}
json.dump(res, open(out, "w"), indent=1)
print(json.dumps(res, indent=1), file=sys.stderr)
