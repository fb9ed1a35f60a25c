"""``sdn3d-train``: train any branch (Hydra config ``conf/train.yaml``).

    sdn3d-train branch=semantic data=synth
    sdn3d-train branch=geometric experiment=demo
    sdn3d-train branch=semantic experiment=semantic_cpu_fullres trainer.max_epochs=30
    sdn3d-train -m branch=geometric ablation=full,no_reproj,full_quaternion,no_tau,single_cad experiment=demo
    sdn3d-train resume=outputs/train/textural/2026-11-22_10-00-00     # continue a run where it stopped

Hydra composes the whole run: ``experiment=<name>`` picks data (and trainer) and the branch's recipe,
``conf/recipe/<branch>_<name>.yaml``; command-line overrides are applied last, so they win. An experiment
the branch has no recipe for stops before anything runs, listing the recipes there are.

``resume=<run dir>`` continues a run from its ``checkpoints/last.ckpt``, wherever the run directory now is (a
copied or moved run resumes into itself); the rest of the command line is applied to the run's saved config or
refused (``branch=`` and other group choices, ``run_dir=``, ``ckpt_path=``, a key the saved config lacks). A
budget smaller than the run has trained, or an inference export where a training checkpoint is needed
(``ckpt_path=``, a run's ``last.ckpt``), stops before anything is written. A resume of a finished run (status ok,
its whole ``trainer.max_epochs`` / ``max_steps`` trained) without a larger budget says so and changes nothing.
A resume that fails before it writes a checkpoint leaves the run's ``summary.json`` as it was; every attempt,
ok or failed, appends its summary to ``<run dir>/summary_log.jsonl`` (and to ``summary_file``).

Exit status: 0 when the run finished with status ok (or a resume had nothing to do); 2 after a user's mistake (a
bad setting or override, an unknown config key, a data file, a resume target or checkpoint:
``sdn3d-train: error: <message>``, one line); 1 when the run failed (a diverged loss: one line) or on any other
error (with its traceback). Either way a run that started has recorded its summary.

Lightning is imported only in ``lightning_modules/``, and there only once the checks before a run have passed
(:mod:`lightning_modules.train`): a refused run answers without it. The library stays usable without Lightning.
"""

from __future__ import annotations

import hashlib
import logging
import sys

from hydra.core.hydra_config import HydraConfig
from omegaconf import DictConfig, OmegaConf

from sdn3d.cli._config import hydra_cli

log = logging.getLogger("sdn3d.train")


def short_job_name(overrides: str, limit: int = 80) -> str:
    """A sweep job's directory name from its overrides, cut to ``limit`` characters plus a hash.

    File systems limit names to 255 bytes; paths in overrides (data.root=...) easily exceed that.
    """
    name = overrides.replace("/", "_") or "default"
    if len(name) <= limit:
        return name
    return name[:limit] + "-" + hashlib.sha1(overrides.encode()).hexdigest()[:8]


def first_set(value, default):
    """``value`` unless it is null/empty, else ``default`` (``oc.select`` returns a null value as is)."""
    return default if value in (None, "", "None", "null") else value


def unless_set(value, default):
    """``default`` when ``value`` is null/empty, else None (e.g. no Hydra output subdirectory for ``resume=``)."""
    return default if value in (None, "", "None", "null") else None


OmegaConf.register_new_resolver("sdn3d_job_name", short_job_name, replace=True)
OmegaConf.register_new_resolver("sdn3d_first_set", first_set, replace=True)
OmegaConf.register_new_resolver("sdn3d_unless_set", unless_set, replace=True)


def _remove_unstarted_run_dirs(cfg: DictConfig) -> None:
    """After a training refused before it started (a bad ``ckpt_path=``, an override, ...): remove the run directory
    Hydra made for it (and ``run_dir`` if another) when it holds nothing but this job's log, so a refusal leaves no
    empty run behind. A directory holding anything else (a run, another run's lock) is left as it is."""
    from pathlib import Path

    hydra = HydraConfig.get()
    log_name = f"{hydra.job.name}.log"
    for folder in {Path(str(hydra.runtime.output_dir)), Path(str(cfg.get("run_dir") or hydra.runtime.output_dir))}:
        if cfg.get("resume") or not folder.is_dir():
            continue
        entries = list(folder.iterdir())
        if all(e.name == log_name and e.is_file() for e in entries):
            for entry in entries:
                entry.unlink()
            try:
                folder.rmdir()
            except OSError:
                continue


@hydra_cli("train", "train")
def main(cfg: DictConfig) -> float | None:
    from lightning_modules.train import run_training
    from sdn3d.cli._errors import report_user_error, user_errors
    from sdn3d.training.errors import RunFailedError

    overrides = list(HydraConfig.get().overrides.task)
    try:
        summary = run_training(cfg, overrides)
    except RunFailedError as exc:  # recorded in the run's summary; not a bug
        log.error("%s", exc)
        sys.exit(1)
    except user_errors() as exc:
        _remove_unstarted_run_dirs(cfg)
        sys.exit(report_user_error("train", exc))
    # the run's own monitor: a resume's composed cfg is the default branch's, not the resumed run's saved config
    monitor = summary.get("monitor")
    metric = summary["metrics"].get(str(monitor))
    log.info("run finished: %s (%s = %s)", summary["run_dir"], monitor, metric)
    return metric  # for Hydra sweepers that optimise the monitored metric


if __name__ == "__main__":
    main()
