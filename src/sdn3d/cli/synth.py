"""``sdn3d-synth``: generate the synthetic Virtual KITTI 1.3.1 dataset (config ``conf/synth.yaml``).

Every option is a Hydra override, e.g. ``sdn3d-synth frames_per_sequence=20 overwrite=true``.
Relative ``output_dir`` paths are resolved against the directory the command starts in.
At the end it prints the class statistics of the new dataset (pixel share and segments per class and world,
for every frame and for the test part; :mod:`sdn3d.data.synth.class_stats`), also written to
``class_statistics.json`` in the dataset root.
Every setting is checked (type and range, :class:`sdn3d.data.synth.SynthConfig`) before any work.
``overwrite=true`` replaces only an earlier dataset of this tool (a directory holding
``synth_manifest.json``), never the working directory, the home directory, their parents or ``/``.
Exit status: 0 done; 2 bad input (a bad setting, an unknown key or bad override syntax, an output_dir that may
not be written: one line on stderr).
"""

from __future__ import annotations

import logging

import hydra
from omegaconf import DictConfig, OmegaConf

from sdn3d.cli._config import hydra_cli
from sdn3d.cli._errors import exit_on_error, run_cli
from sdn3d.data.synth import SynthConfig, generate_dataset
from sdn3d.data.synth.class_stats import PARTS, STATISTICS_NAME, format_table, read_class_statistics
from sdn3d.errors import InputError

log = logging.getLogger(__name__)

_FIELDS = (
    "output_dir",
    "seed",
    "image_size",
    "worlds",
    "variations",
    "frames_per_sequence",
    "cars_per_frame",
    "edit_pairs",
    "occluder_pairs",
    "max_edit_operations",
    "edit_delete_share",
    "overwrite",
    "workers",
    "threads",
    "vehicles",
    "counterfactual_cars",
    "counterfactual_turns",
    "counterfactual_delete",
    "camera_height",
    "camera_pitch",
)


def config_from_hydra(cfg: DictConfig) -> SynthConfig:
    """Build a :class:`SynthConfig` from the composed config; unknown keys are an error."""
    data = OmegaConf.to_container(cfg, resolve=True)
    if not isinstance(data, dict):
        raise InputError("the synth config must be a mapping")
    data.pop("hydra", None)
    unknown = sorted(set(data) - set(_FIELDS))
    if unknown:
        raise InputError(f"unknown synth config keys {unknown}; known: {list(_FIELDS)}")
    if "output_dir" in data:
        out = data["output_dir"]
        if isinstance(out, bool) or not isinstance(out, (str, int)) or not str(out):
            raise InputError(f"output_dir must be a non-empty path, got {out!r}")
        data["output_dir"] = hydra.utils.to_absolute_path(str(out))
    return SynthConfig(**data)


@hydra_cli("synth", "synth")
def main(cfg: DictConfig) -> None:
    exit_on_error(run_cli("synth", _generate, cfg))


def _generate(cfg: DictConfig) -> None:
    config = config_from_hydra(cfg)
    log.info(
        "generating %d world(s) x %d variation(s) x %d frames (+%d edit targets) at %dx%d into %s",
        len(config.worlds),
        len(config.variations),
        config.frames_per_sequence,
        config.target_frames,
        *config.image_size,
        config.output_dir,
    )
    out = generate_dataset(config, progress=True)  # frames done / total, frames/s, ETA on stderr
    stats = read_class_statistics(out)
    for part in PARTS:
        log.info("%s", format_table(stats, part))
    log.info("wrote %s (class statistics: %s)", out, out / STATISTICS_NAME)


if __name__ == "__main__":
    main()
