"""What is checked before a run writes anything: the checkpoint training continues from, the budget, ``threads``
(and ``threads_later``)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from omegaconf import DictConfig, OmegaConf

from sdn3d.errors import UserInputError
from sdn3d.training.errors import TrainingError

__all__ = ["StartPoint", "ThreadsLater", "check_overrides", "check_start", "check_threads", "threads_later"]


@dataclass
class StartPoint:
    """Where fitting starts: the training checkpoint ``ckpt_path`` names (None: from scratch), how far it had got
    (``epochs`` whose training finished, optimiser ``steps``), and whether that already reaches the config's budget
    (``finished``: fitting has nothing left to do; ``budget`` says which limit and ``larger`` a larger one, for
    messages); ``checkpoint_dirs``: where its checkpoint callbacks wrote (``{callback state key: dirpath}``)."""

    checkpoint: Path | None = None
    epochs: int = 0
    steps: int = 0
    finished: bool = False
    budget: str = ""
    larger: str = ""
    checkpoint_dirs: dict[str, str] = field(default_factory=dict)


def _budget(cfg: DictConfig) -> tuple[int | None, int | None]:
    """``(max_epochs, max_steps)`` of the trainer config, None for no limit (Lightning's rules: both unset is 1000
    epochs; -1 is none)."""
    trainer = cfg.get("trainer") or {}
    epochs, steps = trainer.get("max_epochs"), trainer.get("max_steps", -1)
    steps = None if steps in (None, -1) else int(steps)
    if epochs is None:
        return (1000 if steps is None else None), steps
    return (None if int(epochs) == -1 else int(epochs)), steps


def check_start(cfg: DictConfig) -> StartPoint:
    """Check the checkpoint training continues from (``ckpt_path``; ``resume=`` sets it to the run's ``last.ckpt``)
    before anything is written: it must be a Lightning *training* checkpoint of this branch, and the config's budget
    (``trainer.max_epochs`` / ``max_steps``) may not be smaller than what it has trained. Its tensors are mapped, not
    read.

    Raises:
        TrainingError: naming the file: missing or unreadable, an inference export or other weights-only file (no
            optimiser or loop state to continue), another branch's checkpoint, or a budget below its progress.
    """
    if not cfg.get("ckpt_path"):
        return StartPoint()
    from sdn3d.inference_export import is_inference_export
    from sdn3d.io import checkpoint_branch, load_torch_file

    path = Path(str(cfg.ckpt_path)).expanduser()
    what = f"resume={str(cfg.resume)!r}: its checkpoint" if cfg.get("resume") else "ckpt_path"
    if not path.is_file():
        raise TrainingError(f"{what} {str(path)!r} does not exist")
    try:
        content = load_torch_file(path, "checkpoint", mmap=True)
    except UserInputError as exc:
        raise TrainingError(f"{what}: {exc}") from exc
    if is_inference_export(content):
        raise TrainingError(
            f"{what} {str(path)!r} is an sdn3d inference export (weights only, as sdn3d-export-weights and "
            "checkpoints/inference.pt hold them): training can only continue from a Lightning training checkpoint, "
            "which also holds the optimiser and loop state (a run's checkpoints/last.ckpt or best-*.ckpt)")
    needed = ("state_dict", "pytorch-lightning_version", "optimizer_states", "loops")
    lacking = [k for k in needed if not isinstance(content, Mapping) or k not in content]
    if lacking:
        raise TrainingError(f"{what} {str(path)!r} is not a Lightning training checkpoint (it lacks "
                            f"{', '.join(map(repr, lacking))}): training can only continue from one (a run's "
                            "checkpoints/last.ckpt or best-*.ckpt)")
    branch, held = cfg.get("branch_name"), checkpoint_branch(content)
    if branch and held and held != str(branch):
        raise TrainingError(f"{what} {str(path)!r} holds the {held} branch's weights, not the {branch} branch's")
    try:
        epochs = int(content["loops"]["fit_loop"]["epoch_progress"]["current"]["processed"])
    except (KeyError, TypeError, ValueError):
        epochs = int(content.get("epoch") or 0)
    steps = int(content.get("global_step") or 0)
    max_epochs, max_steps = _budget(cfg)
    done = f"{epochs} epoch(s), {steps} optimiser step(s)"
    if max_epochs is not None and max_epochs < epochs or max_steps is not None and max_steps < steps:
        limit = (f"trainer.max_epochs={max_epochs}" if max_epochs is not None and max_epochs < epochs
                 else f"trainer.max_steps={max_steps}")
        raise TrainingError(f"{what} {str(path)!r} has trained {done}: {limit} is less than that; give a budget of "
                            "at least what it has trained (more to train it longer)")
    reached = []
    if max_epochs is not None and epochs >= max_epochs:
        reached.append(f"trainer.max_epochs={max_epochs}")
    if max_steps is not None and steps >= max_steps:
        reached.append(f"trainer.max_steps={max_steps}")
    states = content.get("callbacks")
    dirs = {str(k): v["dirpath"] for k, v in states.items() if isinstance(v, Mapping) and isinstance(
        v.get("dirpath"), str)} if isinstance(states, Mapping) else {}
    if not reached:
        return StartPoint(path, epochs, steps, checkpoint_dirs=dirs)
    more = (f"trainer.max_epochs={epochs + 10}" if max_epochs is not None and epochs >= max_epochs
            else f"trainer.max_steps={steps + 1000}")
    return StartPoint(path, epochs, steps, True, f"{done}, all of its budget ({' and '.join(reached)})", more, dirs)


def check_threads(cfg: DictConfig) -> None:
    """Refuse ``threads`` unless it is null (PyTorch's default) or a positive integer, as ``sdn3d-edit`` does, and a
    ``threads_later`` that :func:`threads_later` refuses.

    Raises:
        TrainingError: naming the setting and the value given.
    """
    threads = cfg.get("threads")
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int) or threads < 1):
        raise TrainingError(f"threads must be a positive integer (torch CPU threads) or null for PyTorch's default, "
                            f"got {threads!r}")
    threads_later(cfg)


@dataclass(frozen=True)
class ThreadsLater:
    """``threads_later``: ``threads`` torch threads from the training epoch after the first ``after_epochs`` on
    (its validation and the test after fitting too); before it, the run's ``threads``."""

    after_epochs: int
    threads: int


def threads_later(cfg: DictConfig) -> ThreadsLater | None:
    """The run's ``threads_later`` (null: None).

    Raises:
        TrainingError: not a mapping of exactly ``after_epochs`` (an integer >= 0) and ``threads`` (>= 1), naming the
            key and the value given.
    """
    node = cfg.get("threads_later")
    if node is None:
        return None
    value = OmegaConf.to_container(node, resolve=True) if OmegaConf.is_config(node) else node
    if not isinstance(value, Mapping) or set(value) != {"after_epochs", "threads"}:
        raise TrainingError(f"threads_later must be null or {{after_epochs: E, threads: T}}, got {value!r}")
    for key, least in (("after_epochs", 0), ("threads", 1)):
        v = value[key]
        if isinstance(v, bool) or not isinstance(v, int) or v < least:
            raise TrainingError(f"threads_later.{key} must be an integer >= {least}, got {v!r}")
    return ThreadsLater(int(value["after_epochs"]), int(value["threads"]))


def _leaves(node: Any, name: str, key: str = "") -> list[str]:
    """The dotted keys of the settings called ``name`` inside the sections of ``node`` (a plain config tree)."""
    found = []
    if isinstance(node, Mapping):
        for child, value in node.items():
            dotted = f"{key}.{child}" if key else str(child)
            if key and child == name and not isinstance(value, Mapping):
                found.append(dotted)
            found.extend(_leaves(value, name, dotted))
    return found


def check_overrides(cfg: DictConfig, overrides: list[str] | None) -> None:
    """Refuse a command line ``+key=value`` that added a top-level setting nothing reads (``+max_epochs=2``, which
    Hydra's own advice for an unknown key suggests), naming the setting of that name in a section
    (``trainer.max_epochs``). A ``+group=option`` (a config group) and ``+section.key=value`` are not refused.

    Raises:
        TrainingError: naming the override and the setting it was likely meant for.
    """
    from hydra.core.override_parser.overrides_parser import OverridesParser
    from hydra.errors import HydraException

    texts = [str(o) for o in overrides or []]
    try:
        parsed = OverridesParser.create().parse_overrides(texts)
    except HydraException:
        return  # Hydra (or resume=) reports a bad override itself
    tree = OmegaConf.to_container(cfg, resolve=False)
    for text, override in zip(texts, parsed, strict=True):
        key = override.key_or_group
        if not override.is_add() or "." in key or "/" in key or override.package is not None:
            continue
        if key not in cfg or isinstance(cfg._get_node(key), DictConfig):
            continue  # a config group's option (its settings are a section, or global)
        value = text.split("=", 1)[1] if "=" in text else ""
        meant = _leaves(tree, key)
        hint = (f"did you mean {meant[0]}={value}?" if meant else
                "settings are named with their section, e.g. trainer.max_epochs=2")
        raise TrainingError(f"{text!r}: sdn3d-train has no top-level setting {key!r}, so nothing would read it; "
                            f"{hint}")
