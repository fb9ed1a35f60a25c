"""Where the Hydra configs live, and composing one in-process (:func:`compose_config`).

The configs sit in ``conf/`` at the repository root (one config group per axis of
variation). The package is installed editable, so the entry points find them next to
``src/``; ``SDN3D_CONFIG_DIR`` overrides the location (e.g. for a copied config tree).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sdn3d.errors import InputError


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


def synth_data_source(root: str | os.PathLike, image_size: Sequence[int] | None = None) -> Any:
    """A synthetic (Virtual KITTI 1.3.1-format) dataset at ``root`` as a :class:`~sdn3d.data.sources.SourceConfig`
    with the settings of ``conf/data/synth.yaml``, at ``image_size [W, H]`` (None: that file's size)."""
    from omegaconf import OmegaConf

    from sdn3d.data.sources import SourceConfig

    data = OmegaConf.load(Path(CONFIG_DIR, "data", "synth.yaml"))
    data.root = str(Path(root).resolve())
    if image_size is not None:
        data.image_size = [int(v) for v in image_size]
    return SourceConfig.from_mapping(data)


def compose_config(overrides: Sequence[str], name: str) -> Any:
    """Compose ``conf/<name>.yaml`` with Hydra ``overrides`` (no run directory, no logging set-up)."""
    from hydra import compose, initialize_config_dir
    from hydra.core.global_hydra import GlobalHydra
    from hydra.errors import HydraException
    from omegaconf.errors import OmegaConfBaseException

    GlobalHydra.instance().clear()  # an earlier in-process Hydra app (e.g. a test) may have left it set
    try:
        with initialize_config_dir(config_dir=CONFIG_DIR, version_base="1.3"):
            return compose(name, overrides=list(overrides))
    except (HydraException, OmegaConfBaseException) as exc:
        raise InputError(f"bad configuration override: {exc}") from exc
