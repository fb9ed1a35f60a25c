"""The de-rendered, editable scene: :class:`~sdn3d.scene.code.SceneCode` and what is made from it.

``code`` (the representation itself), ``io`` (its JSON + NPZ files), ``maps`` (the composed instance,
label, depth, normal and pose maps of a scene) and ``fill`` (per-pixel texture codes, background
refill of vacated pixels).
"""
