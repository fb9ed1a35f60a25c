"""``sdn3d-train``: train any branch (Hydra config ``conf/train.yaml``).

    sdn3d-train branch=semantic data=synth
    sdn3d-train branch=geometric experiment=demo
    sdn3d-train -m branch=geometric ablation=full,no_reproj,full_quaternion,no_tau,single_cad experiment=demo
    sdn3d-train resume=outputs/train/textural/2026-11-22_10-00-00     # continue a run where it stopped

Lightning is imported only here and in ``lightning_modules/``: the library stays usable without it.
"""

from __future__ import annotations

import logging
import sys

import hydra
from hydra.core.hydra_config import HydraConfig
from omegaconf import DictConfig

import sdn3d.cli._config

log = logging.getLogger("sdn3d.train")


@hydra.main(config_path=sdn3d.cli._config.CONFIG_DIR, config_name="train", version_base="1.3")
def main(cfg: DictConfig) -> float | None:
    from lightning_modules.train import TrainingError, run_training

    overrides = list(HydraConfig.get().overrides.task)
    try:
        summary = run_training(cfg, overrides)
    except TrainingError as exc:
        log.error("%s", exc)
        sys.exit(1)
    metric = summary["metrics"].get(str(cfg.get("monitor")))
    log.info("run finished: %s (%s = %s)", summary["run_dir"], cfg.get("monitor"), metric)
    return metric  # for Hydra sweepers that optimise the monitored metric


if __name__ == "__main__":
    main()
