"""Fault-injection helpers for the tests (importable as ``faults`` from tests/, like ``helpers``).

``faults.processes``: run a command in its own process group, wait until it has written something,
SIGKILL it, list what survives. Other modules next to it inject faults into data and checkpoints.
"""
