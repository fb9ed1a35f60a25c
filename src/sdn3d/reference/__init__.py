"""Reference implementations: slow, obvious versions of optimised library functions.

They are not used by the library itself; tests pin the fast paths' results to them and the
``benchmarks/`` time the two side by side. ``scene_maps``: full-frame dense scene composition;
``editing``: edits applied with dense footprints.
"""
