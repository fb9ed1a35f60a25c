# ruff: noqa: E401, E402, E501, E701, E702, E731, F401, I001, B023
"""CPU seconds (time.process_time, all threads) of each phase of one whole `sdn3d-edit` call, no profiler.

    python phases.py OUT.json -- <sdn3d-edit overrides...>
Wraps named functions (module attributes, looked up at call time) and sums their CPU seconds; startup = CPU
seconds from interpreter start until the CLI's main starts (imports of torch, kornia, sdn3d...).
"""
import json, sys, time, runpy, functools, importlib
t0 = time.process_time(); w0 = time.perf_counter()
out = sys.argv[1]; args = sys.argv[3:]
sys.argv = ["sdn3d-edit", *args]
import sdn3d.cli.edit as E
t_imp = time.process_time()
acc = {}
def wrap(modname, attr, label):
    m = importlib.import_module(modname)
    obj = m
    parts = attr.split(".")
    for p in parts[:-1]: obj = getattr(obj, p)
    f = getattr(obj, parts[-1])
    @functools.wraps(f)
    def g(*a, **k):
        s = time.process_time(); sw = time.perf_counter()
        try: return f(*a, **k)
        finally:
            e = acc.setdefault(label, [0.0, 0.0, 0]); e[0] += time.process_time() - s; e[1] += time.perf_counter() - sw; e[2] += 1
    setattr(obj, parts[-1], g)
for spec in [("sdn3d.cli.edit", "run_edit", "run_edit (all after imports)"),
             ("sdn3d.cli.edit", "load_models", "load the three branches"),
             ("sdn3d.derender", "_semantics_and_instances", "semantic branch"),
             ("sdn3d.box_masks", "grabcut_masks", "GrabCut masks (first pass)"),
             ("sdn3d.derender", "_geometry", "geometric branch"),
             ("sdn3d.geometric.fit", "_search", "fit: coarse search"),
             ("sdn3d.geometric.fit", "_stage", "fit: every Adam stage (search's two + fine)"),
             ("sdn3d.geometric.fit", "fit_to_masks", "fit: fit_to_masks (all)"),
             ("sdn3d.box_masks", "refine_with_silhouettes", "GrabCut seeded by the fitted shape (second pass)"),
             ("sdn3d.derender", "encode_scene", "textural encoder"),
             ("sdn3d.editing.session", "EditSession.edit", "edit + render (session.edit)"),
             ("sdn3d.cli.edit", "_write_outputs", "write outputs")]:
    wrap(*spec)
try:
    E.main()
except SystemExit:
    pass
res = {"startup: interpreter + imports (CPU s)": round(t_imp, 2), "process CPU s": round(time.process_time(), 2),
       "process wall s (from interpreter start of this script)": round(time.perf_counter() - w0, 2),
       **{k: {"cpu_s": round(v[0], 3), "wall_s": round(v[1], 3), "calls": v[2]} for k, v in acc.items()}}
print(json.dumps(res, indent=1), file=sys.stderr)
json.dump(res, open(out, "w"), indent=1)
