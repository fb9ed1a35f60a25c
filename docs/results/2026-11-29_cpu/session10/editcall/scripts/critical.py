# ruff: noqa: E402, E501, E701, E702
"""critical.py OUT.json -- <sdn3d-edit overrides>: one call in this process, with each thread's own CPU seconds
(time.thread_time) at the points where this branch runs work on a second Python thread, to estimate the call's wall
time on two idle cores on a busy machine (where wall seconds say nothing): the main thread's CPU seconds (start-up
included) plus, at each join, what the other thread's work took beyond the main thread's share (its wait).
Threads torch or the kernel start themselves (OpenMP, the kernel's std::threads) are not on the main thread: their
work counts as overlapped. Works on both trees (the base has no second thread: waits 0)."""
import functools
import json
import sys
import threading
import time

T0 = time.perf_counter()
out, args = sys.argv[1], sys.argv[3:]
import sdn3d.cli.edit as edit
import sdn3d.derender as der
import sdn3d.geometric.fit as fit

log = []  # (what, thread, thread cpu s)
def timed(owner, name, what):
    inner = getattr(owner, name)
    @functools.wraps(inner)
    def run(*a, **k):
        t = time.thread_time()
        try: return inner(*a, **k)
        finally: log.append((what, threading.get_ident(), time.thread_time() - t))
    setattr(owner, name, run)
timed(der, "_semantics_and_instances", "semantic")
if hasattr(der, "box_grabcut"): timed(der, "box_grabcut", "grabcut")
timed(fit, "_stage", "stage")
main_id = threading.get_ident()
waits = []
if hasattr(fit, "_in_parts"):
    inner = fit._in_parts
    def parts(*a, **k):
        start = len(log)
        r = inner(*a, **k)
        per = {}
        for _what, tid, cpu in log[start:]: per[tid] = per.get(tid, 0.0) + cpu
        mine = per.pop(main_id, 0.0)
        waits.append(("fit stage in parts", round(mine, 3), [round(v, 3) for v in per.values()], round(max([0.0] + [v - mine for v in per.values()]), 3)))
        return r
    fit._in_parts = parts
if hasattr(der, "box_grabcut"):
    inner_d = der.derender
    def derender(*a, **k):
        start = len(log)
        r = inner_d(*a, **k)
        sem = sum(c for w, t, c in log[start:] if w == "semantic")
        gc = sum(c for w, t, c in log[start:] if w == "grabcut" and t != main_id)
        waits.append(("grabcut beside the semantic branch", round(sem, 3), [round(gc, 3)], round(max(0.0, gc - sem), 3)))
        return r
    der.derender = derender  # editing.session calls it through the module
code = edit.main(args)
main_cpu = time.thread_time()
res = {"process_cpu_s": round(time.process_time(), 3), "process_wall_s": round(time.perf_counter() - T0, 3),
       "main_thread_cpu_s": round(main_cpu, 3), "waits": waits,
       "estimated_idle_wall_s": round(main_cpu + sum(w[3] for w in waits), 3)}
json.dump(res, open(out, "w"), indent=1); print(json.dumps(res), file=sys.stderr)
