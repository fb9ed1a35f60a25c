"""Where the Hydra configs live.

The configs sit in ``conf/`` at the repository root (one config group per axis of
variation). The package is installed editable, so the entry points find them next to
``src/``; ``SDN3D_CONFIG_DIR`` overrides the location (e.g. for a copied config tree).
"""

from __future__ import annotations

import os
from pathlib import Path


def config_dir() -> str:
    override = os.environ.get("SDN3D_CONFIG_DIR")
    if override:
        path = Path(override).expanduser().resolve()
        if not path.is_dir():
            raise FileNotFoundError(f"SDN3D_CONFIG_DIR={override!r} is not a directory")
        return str(path)
    path = Path(__file__).resolve().parents[3] / "conf"
    if not path.is_dir():
        raise FileNotFoundError(
            f"sdn3d configs not found at {path}; install sdn3d editable from a checkout "
            "(pip install -e .) or set SDN3D_CONFIG_DIR to the conf/ directory"
        )
    return str(path)


CONFIG_DIR = config_dir()
