"""Inference exports of the trained branches: the weights a predictor needs and nothing else.

A branch's Lightning checkpoint (``sdn3d-train``'s ``<run>/checkpoints/*.ckpt``) also carries the optimizer
state, the loops' and callbacks' state, random-number states and every network only training uses (the
discriminator, ...): 130 MB for the demo's semantic branch, of which its predictor reads 65. An *inference
export* (:data:`EXPORT_NAME`, ``inference.pt``, written beside the checkpoint by ``sdn3d-train`` and by
``sdn3d-export-weights``) is one ``torch.save`` file, read with ``torch.load(weights_only=True)`` and
without Lightning, holding a mapping::

    format            'sdn3d-inference-weights' (:data:`EXPORT_FORMAT`): how a file is recognised
    format_version    1 (:data:`EXPORT_VERSION`); a file of another version is refused, naming it
    branch            'semantic' | 'geometric' | 'textural'
    state_dict        the predictor's weights under the Lightning module's names (:data:`PREDICTOR_PREFIXES`:
                      'net.*'; 'generator.*' and 'encoder.*'), on the CPU
    hyper_parameters  the module's hyper-parameters (plain data): they rebuild the network
    settings          what the branch's predictor needs beyond its module: the geometric run's crop_size and
                      margin (its config.yaml's datamodule settings), the semantic run's image_size (the [W, H]
                      of its training frames), so a copied export keeps them
    source            the checkpoint it was made from: file (name), path (absolute, when exported), sha256,
                      size, mtime_ns, epoch, global_step

:func:`load_branch_weights` reads either kind of file, telling them apart by their content, and returns
:class:`BranchWeights`; every predictor's ``from_checkpoint`` goes through it.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from sdn3d.errors import UserInputError
from sdn3d.io import (
    CHECKPOINT_BRANCHES,
    TorchFiles,
    atomic_write,
    check_lightning_checkpoint,
    checkpoint_branch,
    file_sha256,
    load_torch_file,
)

__all__ = ["ExportWriteError", "EXPORT_FORMAT", "EXPORT_VERSION", "EXPORT_NAME", "PREDICTOR_PREFIXES", "BranchWeights",
           "is_inference_export", "load_branch_weights", "module_with_weights", "inference_export",
           "check_export_target", "write_inference_export", "read_export_source", "export_matches"]

ModuleT = TypeVar("ModuleT")

EXPORT_FORMAT = "sdn3d-inference-weights"
EXPORT_VERSION = 1
#: The file name ``sdn3d-train`` gives the export of a run's selected checkpoint, in its ``checkpoints/``.
EXPORT_NAME = "inference.pt"
#: The ``state_dict`` entries each branch's predictor reads (all else in a checkpoint is training state).
PREDICTOR_PREFIXES: dict[str, tuple[str, ...]] = {"semantic": ("net.",), "geometric": ("net.",),
                                                  "textural": ("generator.", "encoder.")}
_SOURCE_KEYS = ("file", "sha256", "size", "mtime_ns")



class ExportWriteError(UserInputError):
    """An inference export could not be written (a full disk, a permission); the message names the file."""


@dataclass(frozen=True)
class BranchWeights:
    """One branch's weights as a predictor needs them, read from a checkpoint or an export.

    Attributes:
        branch: ``'semantic'``, ``'geometric'`` or ``'textural'``.
        path: the file they were read from (named in errors).
        state_dict: the weights under the Lightning module's names (``net.*``; ``generator.*``, ``encoder.*``).
        hyper_parameters: the module's hyper-parameters.
        settings: the export's ``settings`` (the geometric run's ``crop_size`` and ``margin``, the semantic run's
            ``image_size``); empty for a Lightning checkpoint.
        source: the export's ``source`` record; None for a Lightning checkpoint.
    """

    branch: str
    path: Path
    state_dict: Mapping[str, Any]
    hyper_parameters: Mapping[str, Any]
    settings: Mapping[str, Any] = field(default_factory=dict)
    source: Mapping[str, Any] | None = None

    @property
    def is_export(self) -> bool:
        return self.source is not None


def is_inference_export(content: Any) -> bool:
    """Whether a loaded file's content is an inference export (its ``format`` says so)."""
    return isinstance(content, Mapping) and content.get("format") == EXPORT_FORMAT


def load_branch_weights(path: str | os.PathLike, branch: str, map_location: Any = "cpu",
                        files: TorchFiles | None = None) -> BranchWeights:
    """``branch``'s weights from ``path``: an inference export or a Lightning checkpoint (told apart by content),
    read with ``torch.load(weights_only=True)``; through ``files`` where given (:class:`~sdn3d.io.TorchFiles`: a file
    it read before is not read again; mapped with its ``mmap``), else read whole.

    Raises:
        UserInputError: naming the file: missing or unreadable, neither kind of file, another branch's weights,
            an export of another format version or with malformed entries.
    """
    if branch not in CHECKPOINT_BRANCHES:
        raise ValueError(f"branch must be one of {sorted(CHECKPOINT_BRANCHES)}, got {branch!r}")
    path = Path(path).expanduser()
    content = (files or TorchFiles()).load(path, "checkpoint", map_location)
    if is_inference_export(content):
        return _checked_export(path, content, branch)
    if not isinstance(content, dict) or "state_dict" not in content:
        raise UserInputError(f"{str(path)!r} is not a Lightning checkpoint (needs 'state_dict') nor an sdn3d "
                             f"inference export (format {EXPORT_FORMAT!r})")
    ckpt = check_lightning_checkpoint(path, content, ("state_dict",), branch)
    return BranchWeights(branch, path, ckpt["state_dict"], dict(ckpt.get("hyper_parameters") or {}))


def _checked_export(path: Path, content: Mapping[str, Any], branch: str) -> BranchWeights:
    """:class:`BranchWeights` of a loaded export, every entry checked (errors name ``path``)."""
    where = f"inference export {str(path)!r}"
    version = content.get("format_version")
    if version != EXPORT_VERSION:
        raise UserInputError(f"{where} has format_version {version!r}; this sdn3d reads version {EXPORT_VERSION}: "
                             f"export the checkpoint again (sdn3d-export-weights <checkpoint>)")
    held = content.get("branch")
    if held not in CHECKPOINT_BRANCHES:
        raise UserInputError(f"{where} names no branch (branch {held!r}); export the checkpoint again")
    if held != branch:
        raise UserInputError(f"{where} holds the {held} branch ({CHECKPOINT_BRANCHES[held][2]}), not the {branch} "
                             f"branch ({CHECKPOINT_BRANCHES[branch][2]}): pass it as the {held} checkpoint")
    import torch

    state = content.get("state_dict")
    prefixes = PREDICTOR_PREFIXES[branch]
    if (not isinstance(state, Mapping) or not state
            or not all(isinstance(k, str) and k.startswith(prefixes) and isinstance(v, torch.Tensor)
                       for k, v in state.items())):
        raise UserInputError(f"{where}: its 'state_dict' is not a non-empty mapping of {branch}-branch weights "
                             f"({', '.join(p + '*' for p in prefixes)} -> tensors); export the checkpoint again")
    for key in ("hyper_parameters", "settings", "source"):
        if not isinstance(content.get(key), Mapping):
            raise UserInputError(f"{where}: its {key!r} is a {type(content.get(key)).__name__}, not a mapping; "
                                 f"export the checkpoint again")
    return BranchWeights(branch, path, state, dict(content["hyper_parameters"]), dict(content["settings"]),
                         dict(content["source"]))


#: In-place tensor methods a layer's random initialisation calls (``torch.nn.init``, ``reset_parameters``, the
#: networks' own ``weight.data.normal_(...)``): on a tensor without storage (meta) they are skipped.
_INIT_METHODS = frozenset({"normal_", "uniform_", "fill_", "zero_", "mul_", "add_", "sub_", "div_", "clamp_",
                           "erfinv_", "copy_", "bernoulli_", "exponential_", "random_"})


def _layers_without_init() -> Any:
    """A torch function mode under which ``torch.empty`` (what layers allocate their parameters with) makes
    tensors without storage (meta) and the initialisation methods of :data:`_INIT_METHODS` skip them, so that
    building a network costs no random initialisation. Anything else (``torch.tensor`` constants, non-persistent
    buffers) is made as usual."""
    import torch
    from torch.overrides import TorchFunctionMode

    class LayersWithoutInit(TorchFunctionMode):
        def __torch_function__(self, func: Any, types: Any, args: tuple = (), kwargs: dict | None = None) -> Any:
            kwargs = dict(kwargs or {})
            if func is torch.empty:
                kwargs["device"] = "meta"
            elif getattr(func, "__name__", "") in _INIT_METHODS:  # torch.nn.init passes its tensor by keyword
                target = args[0] if args else kwargs.get("tensor", kwargs.get("self"))
                if isinstance(target, torch.Tensor) and target.is_meta:
                    return target
            return func(*args, **kwargs)

    return LayersWithoutInit()


def _holds_meta_tensors(module: Any) -> bool:
    """Whether a parameter, buffer or tensor attribute of ``module`` or its children has no storage (meta)."""
    import torch

    for child in module.modules():
        tensors = [*child._parameters.values(), *child._buffers.values(), *vars(child).values()]
        if any(isinstance(t, torch.Tensor) and t.is_meta for t in tensors):
            return True
    return False


def module_with_weights(build: Callable[[], ModuleT], state: Mapping[str, Any], path: str | os.PathLike) -> ModuleT:
    """``build()``'s network holding ``state`` (all of its entries, strictly), without the random initialisation
    of its layers (0.3-0.5 s for the demo's DRN and ResNet-18 on a CPU): the network is built with its
    parameters unallocated (:func:`_layers_without_init`) and takes over ``state``'s tensors (no copy). Where
    that leaves a tensor unallocated (a network that computes a buffer from an initialised one), or fails, it
    is built and loaded the ordinary way.

    Raises:
        UserInputError: naming ``path``, when ``state`` does not fit the network (missing, unexpected or
            differently shaped weights).
    """
    try:
        with _layers_without_init():
            module = build()
        module.load_state_dict(state, strict=True, assign=True)
        if not _holds_meta_tensors(module):
            return module
    except Exception:  # noqa: BLE001 - whatever the fast way trips on, the ordinary way below decides
        pass
    module = build()
    try:
        module.load_state_dict(state, strict=True)
    except RuntimeError as exc:
        reason = " ".join(str(exc).split())
        raise UserInputError(f"the weights of {str(path)!r} do not fit the network its hyper-parameters describe: "
                             f"{reason[:300]}") from exc
    return module


def inference_export(ckpt: Mapping[str, Any], source: str | os.PathLike,
                     settings: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The export (see the module doc) of ``ckpt``, the loaded Lightning checkpoint file ``source``.

    Raises:
        UserInputError: naming ``source``, when its weights are none of the branches'.
    """
    source = Path(source)
    branch = checkpoint_branch(ckpt)
    if branch is None:
        raise UserInputError(f"checkpoint {str(source)!r} holds none of the branches' weights "
                             f"({'; '.join(what for _, _, what in CHECKPOINT_BRANCHES.values())}): nothing to export")
    prefixes = PREDICTOR_PREFIXES[branch]
    state = {k: v.detach().to("cpu").clone() for k, v in ckpt["state_dict"].items() if k.startswith(prefixes)}
    stat = source.stat()
    record = {"file": source.name, "path": str(source.resolve()), "sha256": file_sha256(source),
              "size": stat.st_size, "mtime_ns": stat.st_mtime_ns, "epoch": ckpt.get("epoch"),
              "global_step": ckpt.get("global_step")}
    return {"format": EXPORT_FORMAT, "format_version": EXPORT_VERSION, "branch": branch, "state_dict": state,
            "hyper_parameters": dict(ckpt.get("hyper_parameters") or {}), "settings": dict(settings or {}),
            "source": record}


#: Keys only a Lightning *training* checkpoint holds (its loop and optimizer state): such a file is never replaced.
_TRAINING_KEYS = ("pytorch-lightning_version", "optimizer_states", "loops", "lr_schedulers")


def _existing_kind(path: Path) -> str:
    """What the existing file ``path`` holds: ``'export'``, ``'training checkpoint'`` or ``'other'`` (tensors are
    mapped, not read)."""
    try:
        content = load_torch_file(path, "file", mmap=True)
    except UserInputError:
        return "other"
    if is_inference_export(content):
        return "export"
    if isinstance(content, Mapping) and "state_dict" in content and any(k in content for k in _TRAINING_KEYS):
        return "training checkpoint"
    return "other"


def check_export_target(target: str | os.PathLike, checkpoint: str | os.PathLike, overwrite: bool,
                        default: bool = False) -> None:
    """Raise a :class:`UserInputError` naming ``target`` if an export may not be written there.

    Never replaced: the checkpoint itself, a directory, and a Lightning training checkpoint (its run could no
    longer resume). An existing file otherwise needs ``overwrite``, except that ``default`` (the target is
    :data:`EXPORT_NAME` beside the checkpoint, this tool's own place) replaces an earlier export without it.
    """
    target, checkpoint = Path(target).expanduser(), Path(checkpoint).expanduser()
    if not os.path.lexists(target):
        return
    if target.exists() and target.resolve() == checkpoint.resolve():
        raise UserInputError(f"the export would replace the checkpoint {str(checkpoint)!r}: give another output file")
    if target.is_dir():
        raise UserInputError(f"output {str(target)!r} is a directory: give the export's file name, e.g. "
                             f"{str(target / EXPORT_NAME)!r}")
    kind = _existing_kind(target)
    if kind == "training checkpoint":
        raise UserInputError(f"output {str(target)!r} is a training checkpoint (it holds Lightning's loop and "
                             "optimizer state): refusing to overwrite it, its run could no longer resume; give "
                             "another output file")
    if not overwrite and not (default and kind == "export"):
        what = "an inference export" if kind == "export" else "a file"
        raise UserInputError(f"output {str(target)!r} exists ({what}): refusing to overwrite it; give another "
                             "output file or pass --overwrite")


def write_inference_export(checkpoint: str | os.PathLike, ckpt: Mapping[str, Any],
                           out: str | os.PathLike | None = None, settings: Mapping[str, Any] | None = None,
                           overwrite: bool = False) -> Path:
    """Write the export of ``ckpt`` (the loaded content of ``checkpoint``) to ``out`` atomically; returns ``out``.

    ``out`` None: :data:`EXPORT_NAME` beside the checkpoint (an earlier export there is replaced).
    An existing ``out`` is replaced only with ``overwrite``, and never when it is a training checkpoint
    (:func:`check_export_target`).

    The export is serialised in memory first: a full disk (or any other failed write) is an
    :class:`ExportWriteError` naming the file, and leaves no temporary file and an earlier ``out`` as it was
    (``torch.save`` into a file the disk refuses fails with a bare ``RuntimeError``, "unexpected pos").

    Raises:
        UserInputError: ``out`` may not be written (:func:`check_export_target`), or the checkpoint holds no
            branch's weights.
        ExportWriteError: ``out`` could not be written (the disk is full, ...).
    """
    import errno
    import io

    import torch

    checkpoint = Path(checkpoint).expanduser()
    target = checkpoint.parent / EXPORT_NAME if out is None else Path(out).expanduser()
    check_export_target(target, checkpoint, overwrite, default=out is None)
    payload = inference_export(ckpt, checkpoint, settings)
    buffer = io.BytesIO()
    torch.save(payload, buffer)
    try:
        return atomic_write(target, lambda handle: handle.write(buffer.getbuffer()))
    except OSError as exc:
        reason = "the disk is full" if exc.errno == errno.ENOSPC else (exc.strerror or str(exc))
        earlier = "the earlier file there is unchanged" if target.exists() else "nothing was written"
        raise ExportWriteError(f"could not write inference export {str(target)!r}: {reason}; {earlier}") from exc


def read_export_source(path: str | os.PathLike, files: TorchFiles | None = None) -> dict[str, Any]:
    """The ``source`` record of the export ``path`` (its tensors are mapped, not read: this costs milliseconds);
    read through ``files`` where given (:class:`~sdn3d.io.TorchFiles`: the models' loading then takes the content
    over instead of unpickling the file again).

    Raises:
        UserInputError: naming the file: unreadable, not an export, or a ``source`` without
            ``file``, ``sha256``, ``size`` and ``mtime_ns``.
    """
    path = Path(path).expanduser()
    content = (files or TorchFiles(mmap=True)).load(path, "inference export")
    if not is_inference_export(content):
        raise UserInputError(f"{str(path)!r} is not an sdn3d inference export (format {EXPORT_FORMAT!r})")
    source = content.get("source")
    if not isinstance(source, Mapping) or any(k not in source for k in _SOURCE_KEYS):
        raise UserInputError(f"inference export {str(path)!r} does not record its source checkpoint "
                             f"({', '.join(_SOURCE_KEYS)})")
    return dict(source)


def export_matches(source: Mapping[str, Any], checkpoint: str | os.PathLike) -> bool:
    """Whether an export's ``source`` record is the file ``checkpoint`` as it is now.

    Its SHA-256 decides; it is only computed (0.1-0.2 s for a 130 MB checkpoint) when the size matches and the
    name or the modification time differs: the same name, size and modification time to the nanosecond are
    taken as the same, unchanged file (a checkpoint written again, or copied without keeping its time, gets
    another one).
    """
    checkpoint = Path(checkpoint)
    stat = checkpoint.stat()
    if stat.st_size != source.get("size"):
        return False
    if stat.st_mtime_ns == source.get("mtime_ns") and checkpoint.name == source.get("file"):
        return True
    return file_sha256(checkpoint) == source.get("sha256")
