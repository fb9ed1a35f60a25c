# ruff: noqa: E402, E501, E701, E702
"""Run sdn3d-edit with an __import__ hook: CPU seconds of each top-level import made after start-up, with its caller."""
import builtins
import sys
import time
import traceback

_orig = builtins.__import__
_depth = [0]
_log = []
def hook(name, globals=None, locals=None, fromlist=(), level=0):
    if level or name in sys.modules or _depth[0]:
        return _orig(name, globals, locals, fromlist, level)
    _depth[0] += 1
    t = time.process_time()
    try:
        return _orig(name, globals, locals, fromlist, level)
    finally:
        _depth[0] -= 1
        dt = time.process_time() - t
        if dt > 0.01:
            fr = [f for f in traceback.extract_stack()[:-1] if 'sdn3d' in f.filename]
            _log.append((dt, name, f"{fr[-1].filename.split('src/')[-1]}:{fr[-1].lineno}" if fr else '?'))
import sdn3d.cli.edit as edit

t0 = time.process_time()
print('startup cpu', t0, file=sys.stderr)
builtins.__import__ = hook
edit.main(sys.argv[1:])
builtins.__import__ = _orig
for dt, n, w in _log: print(f'{dt:.3f} {n} {w}', file=sys.stderr)
print('run cpu', time.process_time() - t0, file=sys.stderr)
