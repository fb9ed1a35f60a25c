"""LightningModules of the three branches (training logic only; models and losses live in sdn3d).

Imported lazily so that ``import lightning_modules.train`` does not build every branch.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__all__ = ["SemanticModule", "GeometricModule", "Deep3DBoxModule", "TexturalModule", "BranchModule"]

_WHERE = {
    "SemanticModule": "lightning_modules.semantic",
    "GeometricModule": "lightning_modules.geometric",
    "Deep3DBoxModule": "lightning_modules.deep3dbox",
    "TexturalModule": "lightning_modules.textural",
    "BranchModule": "lightning_modules._base",
}


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        return getattr(import_module(_WHERE[name]), name)
    raise AttributeError(f"module 'lightning_modules' has no attribute {name!r}")
