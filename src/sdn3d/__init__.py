"""sdn3d: 3D scene de-rendering networks (3D-SDN, NeurIPS 2018) in plain PyTorch.

The library (``sdn3d``) de-renders, edits and re-renders scenes without importing
Lightning; ``lightning_modules`` and ``datamodules`` orchestrate training around it.
"""

__version__ = "0.1.0"
