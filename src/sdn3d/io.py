"""Atomic output writing: every file sdn3d writes goes to a temporary file in the
target directory first and is renamed into place, so a crash or a bad input never
leaves a half-written output or replaces a good one with a broken one.

Whole output directories (``sdn3d-edit``, ``sdn3d-bench``, ``sdn3d-synth``) are staged the same way:
everything goes into a temporary sibling directory that replaces the output directory only once
everything is written, so a failure leaves no partial output and an old result intact. An existing
non-empty directory is only replaced when it holds the tool's ``marker`` file (it is a previous result
of the same tool), never an unrelated folder, and never the working directory, the home directory, one
of their parents or ``/`` (:func:`refuse_unsafe_output_dir`). A staged tree may carry an owner record
(``staged_directory(..., owned=True)``) so that the next run removes what a killed run left behind
(:func:`remove_stale_staging`)."""

from __future__ import annotations

import errno
import io
import json
import logging
import os
import re
import shutil
import signal
import socket
import tempfile
import threading
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from sdn3d.errors import UserInputError

__all__ = [
    "atomic_write", "write_bytes_atomic", "write_text_atomic", "write_json_atomic", "write_png_atomic",
    "check_output_dir", "check_writable", "staged_directory", "swap_into_place", "current_umask",
    "load_torch_file", "TorchFiles", "load_lightning_checkpoint", "check_lightning_checkpoint", "describe_load_failure",
    "checkpoint_branch", "CHECKPOINT_BRANCHES", "file_sha256", "yaml_loader",
    "OutputDirError", "refuse_unsafe_output_dir", "OWNER_FILE", "owner_record", "process_alive",
    "remove_stale_staging", "BusyError", "writer_lock", "DiskFullError", "DISK_FULL_ERRNOS", "is_disk_full",
]

#: ``errno`` values of a full disk (or a full quota).
DISK_FULL_ERRNOS = (errno.ENOSPC, errno.EDQUOT)


class DiskFullError(OSError):
    """A file could not be written because the disk (or the quota) is full; the message names it and says that
    nothing half-written is left. ``errno`` is the original one; ``filename`` the file."""

    def __init__(self, code: int, message: str, filename: str | None = None) -> None:
        super().__init__(code, message)
        self.message, self.filename = message, filename

    def __str__(self) -> str:
        return self.message


def is_disk_full(exc: BaseException) -> bool:
    """Whether ``exc`` is an :class:`OSError` of a full disk or quota."""
    return isinstance(exc, OSError) and exc.errno in DISK_FULL_ERRNOS


def _disk_full(exc: OSError, path: str | os.PathLike, what: str = "") -> DiskFullError:
    return DiskFullError(exc.errno, f"the disk is full: could not write {what}{str(path)!r} "
                                    f"({exc.strerror or os.strerror(exc.errno)}); nothing half-written is left; "
                                    "free some space and try again", str(path))


def current_umask() -> int:
    """The process's umask (read from ``/proc`` where it can be, so the umask itself is never changed)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def cache_dir(kind: str) -> Path:
    """The folder where sdn3d keeps what it builds once per machine and reuses across processes, each entry named by a
    hash of everything it is made from (``kind``: ``native``, the C++ kernels' libraries, :mod:`sdn3d.native`;
    ``meshes``, the simplified template banks): ``$SDN3D_<KIND>_CACHE`` where set, else ``~/.cache/sdn3d/<kind>``."""
    root = os.environ.get(f"SDN3D_{kind.upper()}_CACHE")
    return Path(root) if root else Path.home() / ".cache" / "sdn3d" / kind


def atomic_write(path: str | os.PathLike, writer: Callable[[io.BufferedWriter], None]) -> Path:
    """Call ``writer(file)`` on a temporary file next to ``path``, then rename it onto ``path``.

    The temporary file is removed if ``writer`` raises; ``path`` keeps its old content. The file gets the
    mode a plain ``open()`` would give it under the user's umask (``mkstemp`` alone would make it 0600).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.fchmod(fd, 0o666 & ~current_umask())
        with os.fdopen(fd, "wb") as handle:
            writer(handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        if is_disk_full(exc) and not isinstance(exc, DiskFullError):
            raise _disk_full(exc, path) from exc
        raise
    return path


def write_bytes_atomic(path: str | os.PathLike, data: bytes) -> Path:
    return atomic_write(path, lambda f: f.write(data))


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    return write_bytes_atomic(path, text.encode("utf-8"))


def write_json_atomic(path: str | os.PathLike, obj: Any, indent: int = 2) -> Path:
    return write_text_atomic(path, json.dumps(obj, indent=indent, sort_keys=False) + "\n")


def write_png_atomic(path: str | os.PathLike, array: np.ndarray) -> Path:
    """Write a ``(H, W)`` or ``(H, W, 3)`` uint8/uint16 array as PNG, atomically.

    PNG metadata is fixed (no timestamps), so the same array always gives the same bytes.
    """
    from PIL import Image

    array = np.ascontiguousarray(array)
    if array.dtype == np.uint16 and array.ndim == 2:
        image = Image.fromarray(array)
    elif array.dtype == np.uint8:
        image = Image.fromarray(array)
    else:
        raise ValueError(f"write_png_atomic: {path}: expected uint8 or 2-D uint16 array, got {array.dtype}")

    def _write(handle: io.BufferedWriter) -> None:
        image.save(handle, format="PNG", optimize=False)

    return atomic_write(path, _write)


#: How each branch's Lightning checkpoint is told apart (:func:`checkpoint_branch`): ``state_dict`` key prefixes
#: that only that branch's network has, hyper-parameter names that only its module takes, and what its weights are.
CHECKPOINT_BRANCHES: dict[str, tuple[tuple[str, ...], tuple[str, ...], str]] = {
    "semantic": (("net.seg.", "net.instance.", "net.decoder."), ("arch", "instance_head", "head_channels"),
                 "DRN weights 'net.seg.*'"),
    "geometric": (("net.heads.", "net.mlp."), ("rotation", "distance", "single_cad", "scale_prior"),
                  "GeometricNet weights 'net.heads.*', 'net.mlp.*'"),
    "textural": (("generator.", "encoder."), ("ngf", "nef", "code_dim", "n_downsampling"),
                 "pix2pixHD G and E weights 'generator.*', 'encoder.*'"),
}


def checkpoint_branch(ckpt: Mapping[str, Any]) -> str | None:
    """The branch (``'semantic'``, ``'geometric'``, ``'textural'``) whose weights a loaded Lightning
    checkpoint holds, or None if it cannot tell (:data:`CHECKPOINT_BRANCHES`).

    The ``state_dict`` key prefixes decide; the hyper-parameter names only when no prefix matches.
    """
    state = ckpt.get("state_dict")
    keys = [k for k in state if isinstance(k, str)] if isinstance(state, Mapping) else []
    found = [b for b, (prefixes, _, _) in CHECKPOINT_BRANCHES.items() if any(k.startswith(prefixes) for k in keys)]
    if not found:
        hparams = ckpt.get("hyper_parameters")
        names = {k for k in hparams if isinstance(k, str)} if isinstance(hparams, Mapping) else set()
        found = [b for b, (_, hp_names, _) in CHECKPOINT_BRANCHES.items() if names & set(hp_names)]
    return found[0] if len(found) == 1 else None


def describe_load_failure(exc: BaseException) -> str:
    """One line saying why ``torch.load`` failed (torch's weights-only message is long and advises
    ``weights_only=False``, which would run the file's code: keep only its reason)."""
    text = str(exc)
    if "WeightsUnpickler error:" in text:
        text = text.split("WeightsUnpickler error:", 1)[1].split("Check the documentation", 1)[0]
        reason = "weights-only loading refused it: " + " ".join(text.split())
    else:
        reason = f"{type(exc).__name__}: {' '.join(text.split())}" if text.strip() else type(exc).__name__
    return reason if len(reason) <= 200 else reason[:197] + "..."


def file_sha256(path: str | os.PathLike) -> str:
    """The SHA-256 of a file's bytes, as 64 hex digits (read in chunks: a checkpoint need not fit in memory)."""
    import hashlib

    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        while chunk := handle.read(1 << 20):
            digest.update(chunk)
    return digest.hexdigest()


def yaml_loader() -> type:
    """The safe YAML loader every reader of a YAML file uses: libyaml's (``yaml.CSafeLoader``) where PyYAML was built
    with it, else the pure-Python ``yaml.SafeLoader``. The same documents and errors (the constructors are shared,
    only the parser differs), 10-30 times faster: a run's 170-line ``config.yaml`` took 11 ms with the pure-Python
    parser, read three times in every ``sdn3d-edit`` call (:func:`sdn3d.runs.trained_data`)."""
    import yaml

    return getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def load_torch_file(path: str | os.PathLike, what: str = "checkpoint", map_location: Any = "cpu",
                    mmap: bool = False) -> Any:
    """The content of a file the user named, read with ``torch.load(weights_only=True)`` (no code from the
    file runs); ``what`` names it in errors (``'checkpoint'``, ``'code_bank'``, ...).

    ``mmap``: map the file's tensors instead of reading them (``torch.load(mmap=True)``): reading a few small
    entries of a large file then costs almost nothing, and a network's weights are paged in as it uses them. The
    tensors stay backed by the file. Only torch's zip format can be mapped (what ``torch.save`` writes since
    PyTorch 1.6): a file of the older format is read whole.

    Raises:
        UserInputError: the file is missing, or ``torch.load`` failed in any way (truncated, corrupt, not a
            torch file, objects ``weights_only`` refuses): the file is bad; the exception is kept as the cause.
    """
    import torch

    path = Path(path).expanduser()
    if not path.is_file():
        raise UserInputError(f"{what} {str(path)!r} does not exist")
    try:
        mmap = mmap and _is_zip_file(path)
        return torch.load(path, map_location=map_location, weights_only=True, mmap=mmap)
    except Exception as exc:  # whatever unpickling the user's file raises, the file is bad
        raise UserInputError(f"could not read {what} {str(path)!r}: not a loadable PyTorch file (truncated, corrupt, "
                             f"not a torch file, or holding more than tensors and plain data) "
                             f"[{describe_load_failure(exc)}]") from exc


def _is_zip_file(path: Path) -> bool:
    """Whether ``path`` starts as a zip archive does (its first local file header), the test ``torch.load`` makes
    to tell its zip format from the older one."""
    with path.open("rb") as handle:
        return handle.read(4) == b"PK\x03\x04"


class TorchFiles:
    """The torch files one program reads (:func:`load_torch_file`), each unpickled once however many steps need it:
    ``sdn3d-edit`` reads an inference export when it resolves a run's checkpoints (for its source record) and when it
    loads the models (for their weights); the second :meth:`load` returns the first one's content.

    ``mmap``: map the files' tensors instead of reading them (:func:`load_torch_file`). For a program that ends with
    its call (``sdn3d-edit``): only the pages the networks use are read. A long-running server reads its weights
    whole, so as not to depend on the files staying in place.
    """

    def __init__(self, mmap: bool = False) -> None:
        self.mmap = mmap
        self._content: dict[tuple[Path, str], Any] = {}

    def load(self, path: str | os.PathLike, what: str = "checkpoint", map_location: Any = "cpu") -> Any:
        """:func:`load_torch_file`'s content of ``path`` onto ``map_location``; read once, kept for later calls.

        Raises:
            UserInputError: as :func:`load_torch_file` (a file that failed is not kept: it fails again).
        """
        key = (Path(path).expanduser().resolve(), str(map_location))
        if key not in self._content:
            self._content[key] = load_torch_file(path, what, map_location, mmap=self.mmap)
        return self._content[key]


def load_lightning_checkpoint(path: str | os.PathLike, map_location: Any = "cpu",
                              required: tuple[str, ...] = ("state_dict",), branch: str | None = None) -> dict:
    """A Lightning checkpoint read with ``torch.load(weights_only=True)`` (no code from the file runs).

    Args:
        branch: ``'semantic'``, ``'geometric'`` or ``'textural'``: the file must hold that branch's
            weights (:func:`checkpoint_branch`); None accepts any.

    Raises:
        UserInputError (a ValueError): naming the file: missing, unreadable (truncated, corrupt, not a
            torch file, or holding objects ``weights_only`` refuses: any exception of ``torch.load``,
            kept as the cause), not a mapping with the ``required`` keys, or another branch's checkpoint
            (the message says which branch it holds).
    """
    if branch is not None and branch not in CHECKPOINT_BRANCHES:
        raise ValueError(f"branch must be one of {sorted(CHECKPOINT_BRANCHES)}, got {branch!r}")
    path = Path(path).expanduser()
    return check_lightning_checkpoint(path, load_torch_file(path, "checkpoint", map_location), required, branch)


def check_lightning_checkpoint(path: str | os.PathLike, ckpt: Any, required: tuple[str, ...] = ("state_dict",),
                               branch: str | None = None) -> dict:
    """``ckpt``, the loaded content of ``path``, checked as :func:`load_lightning_checkpoint` checks it.

    Raises:
        UserInputError: naming ``path``: not a mapping with the ``required`` keys, ``state_dict`` or
            ``hyper_parameters`` not mappings, or another branch's checkpoint.
    """
    path = Path(path)
    if not isinstance(ckpt, dict) or any(k not in ckpt for k in required):
        raise UserInputError(f"{str(path)!r} is not a Lightning checkpoint (needs {', '.join(map(repr, required))})")
    for key in ("state_dict", "hyper_parameters"):
        if ckpt.get(key) is not None and not isinstance(ckpt[key], Mapping):
            raise UserInputError(f"{str(path)!r} is not a Lightning checkpoint: its {key!r} is a "
                                 f"{type(ckpt[key]).__name__}, not a mapping")
    if branch is not None:
        _check_branch(path, ckpt, branch)
    return ckpt


def _check_branch(path: Path, ckpt: dict, branch: str) -> None:
    """Raise a :class:`UserInputError` if ``ckpt`` holds another branch's weights, or none of ``branch``'s."""
    held = checkpoint_branch(ckpt)
    if held == branch:
        return
    prefixes, _, what = CHECKPOINT_BRANCHES[branch]
    if held is not None:
        raise UserInputError(f"checkpoint {str(path)!r} holds the {held} branch ({CHECKPOINT_BRANCHES[held][2]}), "
                             f"not the {branch} branch ({what}): pass it as the {held} checkpoint")
    state = ckpt.get("state_dict") or {}
    if not any(isinstance(k, str) and k.startswith(prefixes) for k in state):
        raise UserInputError(f"checkpoint {str(path)!r} is not a {branch}-branch checkpoint: it has none of the "
                             f"{what}")


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextmanager
def _terminate_as_exit() -> Iterator[None]:
    """While the block runs, SIGTERM (when it has its default action: a tool's own handler is left alone) raises
    ``SystemExit(143)``, so the cleanup of the block's ``except`` / ``finally`` runs instead of the process just
    ending (a staged tree left behind). Only in the main thread (where Python runs signal handlers)."""
    if not _in_main_thread() or signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL:
        yield
        return

    def stop(signum: int, frame: Any) -> None:
        raise SystemExit(128 + signum)

    signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


@contextmanager
def _signals_deferred() -> Iterator[None]:
    """SIGINT and SIGTERM arriving while the block runs are held and raised again once it has ended: steps that must
    happen together (the renames of an output swap) are not cut between. Only in the main thread."""
    if not _in_main_thread():
        yield
        return
    held: list[int] = []
    wanted = [s for s in (signal.SIGINT, signal.SIGTERM) if signal.getsignal(s) is not None]  # None: set outside
    previous = {s: signal.signal(s, lambda signum, frame: held.append(signum)) for s in wanted}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        for sig in dict.fromkeys(held):
            signal.raise_signal(sig)


def swap_into_place(tmp: Path, out: Path, owned: bool = False) -> None:
    """Rename the finished tree ``tmp`` onto ``out``; an old ``out`` is moved aside first, then deleted.

    ``owned``: ``tmp`` carries an owner record (:data:`OWNER_FILE`, see :func:`staged_directory`); the tree
    the old ``out`` is moved into gets one too and is deleted before its record, and ``tmp``'s record is
    removed just before the rename, so a run killed at any point leaves only trees that
    :func:`remove_stale_staging` recognises as its own.
    """
    old = None
    with _signals_deferred():  # a Ctrl+C or SIGTERM between the renames would leave no output at all
        if out.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
            if owned:
                write_json_atomic(old / OWNER_FILE, owner_record())
            os.rename(out, old / "tree")
        if owned:
            (tmp / OWNER_FILE).unlink(missing_ok=True)
        os.rename(tmp, out)
    if old is not None:
        if owned:
            _remove_owned_tree(old)
        else:
            shutil.rmtree(old)


class OutputDirError(UserInputError, FileExistsError):
    """An output directory a tool may not write or replace; the message names it and says what to do.

    Also a :class:`FileExistsError` (what these refusals raised before).
    """


def refuse_unsafe_output_dir(out: str | os.PathLike) -> None:
    """Raise :class:`OutputDirError` if ``out`` is a directory that must never be replaced, marker or not:
    the file-system root, the current working directory or one of its parents, the home directory or one
    of its parents. (Replacing an output directory removes the directory itself, not only its files.)
    """
    out = Path(out).expanduser().resolve()
    what = None
    if out == Path(out.anchor):
        what = "the file-system root"
    else:
        try:
            cwd = Path.cwd().resolve()
        except OSError:  # the working directory was removed: nothing there to protect
            cwd = None
        try:
            home = Path.home().resolve()
        except (RuntimeError, KeyError, OSError):  # no HOME and no password entry
            home = None
        if cwd is not None and out == cwd:
            what = "the current working directory"
        elif cwd is not None and out in cwd.parents:
            what = f"a parent of the current working directory {str(cwd)!r}"
        elif home is not None and out == home:
            what = "the home directory"
        elif home is not None and out in home.parents:
            what = f"a parent of the home directory {str(home)!r}"
    if what is not None:
        raise OutputDirError(f"output_dir {str(out)!r} is {what}: refusing to use it as an output directory "
                             "(replacing an output removes the whole directory); choose a dedicated directory "
                             "that does not exist yet, e.g. a new subdirectory")


def _foreign_entries(out: Path, listed: set[str]) -> list[str]:
    """Entries under ``out`` (relative POSIX paths, sorted) that are not in ``listed`` (files an earlier run wrote)
    nor a directory on the way to one: what replacing ``out`` would delete that the tool did not write.
    Symbolic links are entries of their own (never followed)."""
    needed_dirs = {parent.as_posix() for name in listed for parent in Path(name).parents if parent != Path(".")}
    foreign = []
    for root, dirs, files in os.walk(out, followlinks=False):
        base = Path(root).relative_to(out)
        for name in sorted(dirs):
            rel = (base / name).as_posix()
            if (Path(root) / name).is_symlink():
                foreign.append(rel)
            elif rel not in needed_dirs:
                foreign.append(rel + "/")
        dirs[:] = [d for d in dirs if (base / d).as_posix() in needed_dirs and not (Path(root) / d).is_symlink()]
        foreign.extend(rel for rel in ((base / name).as_posix() for name in sorted(files)) if rel not in listed)
    return sorted(foreign)


def _listed_outputs(out: Path, marker: str, listed_in: str, legacy: re.Pattern | None = None) -> set[str]:
    """The files the earlier run in ``out`` wrote: the list under ``listed_in`` in its ``marker`` JSON file (a marker
    of a version that listed none: the files whose relative path ``legacy`` matches, when given)."""
    try:
        record = json.loads((out / marker).read_text(encoding="utf-8"))
        if legacy is not None and isinstance(record, dict) and listed_in not in record:
            return {p.relative_to(out).as_posix() for p in out.rglob("*")
                    if p.is_file() and not p.is_symlink() and legacy.fullmatch(p.relative_to(out).as_posix())
                    } | {marker}
        listed = record[listed_in]
        if not isinstance(listed, list) or not all(isinstance(n, str) for n in listed):
            raise TypeError(listed_in)
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError) as exc:
        raise OutputDirError(f"output_dir {str(out)!r}: its {marker} does not list the files the earlier run wrote "
                             f"({listed_in!r}: {type(exc).__name__}), so what else the directory holds is not known: "
                             "refusing to replace it; choose another output_dir or empty it yourself") from None
    return {Path(n).as_posix() for n in listed} | {marker}


def check_writable(out: str | os.PathLike) -> None:
    """Raise :class:`OutputDirError` unless a directory can be created beside ``out`` (where a staged tree goes):
    the nearest existing ancestor of ``out``'s parent must be a directory in which this process can create one
    (tried: a directory is made and removed, so ``/proc``, read-only mounts and missing permissions all show)."""
    out = Path(out).expanduser().absolute()
    ancestor = out.parent
    while not ancestor.exists() and ancestor != ancestor.parent:
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise OutputDirError(f"output_dir {str(out)!r} cannot be created: {str(ancestor)!r} is not a directory; "
                             "choose another output_dir")
    try:
        probe = tempfile.mkdtemp(prefix=".sdn3d-write-test-", dir=ancestor)
        os.rmdir(probe)
    except OSError as exc:
        raise OutputDirError(f"output_dir {str(out)!r} cannot be written: creating a directory in {str(ancestor)!r} "
                             f"failed ({exc.strerror or exc}); choose a writable output_dir") from None


def check_output_dir(out: str | os.PathLike, marker: str, overwrite: bool, listed_in: str | None = None,
                     inputs: Mapping[str, str | os.PathLike | None] | None = None,
                     legacy: re.Pattern | None = None) -> Path:
    """Raise :class:`OutputDirError` (a ``FileExistsError``) if ``out`` may not be (re)written; returns it resolved.

    An existing directory is refused if it is one :func:`refuse_unsafe_output_dir` protects, or if it is not
    empty and either ``overwrite`` is false or it holds no ``marker`` file (no earlier output of the tool).
    A directory that cannot be created or written beside (:func:`check_writable`) is refused too.

    Args:
        listed_in: the key of the ``marker`` JSON file that lists every file the earlier run wrote (relative
            paths); a directory holding anything else (a user's file, an unlisted directory, a link) is not
            replaced, since that would delete it. None: the marker alone decides.
        inputs: ``{setting: path}`` of the files the run reads (None values skipped): a non-empty ``out`` that
            holds one of them is refused, whatever else (replacing it would delete the run's own input).
        legacy: the relative paths (a pattern) an earlier version of the tool wrote, whose ``marker`` lists no
            files: those count as listed.
    """
    out = Path(out).expanduser().resolve()
    if out.exists() and not out.is_dir():
        raise OutputDirError(f"output_dir {str(out)!r} exists and is not a directory; choose another output_dir")
    if out.is_dir():
        refuse_unsafe_output_dir(out)
    if out.is_dir() and any(out.iterdir()):
        for setting, path in (inputs or {}).items():
            if path is None or str(path) == "":
                continue
            resolved = Path(str(path)).expanduser().resolve()
            if resolved == out or out in resolved.parents:
                raise OutputDirError(f"{setting} {str(path)!r} lies inside output_dir {str(out)!r}, which the results "
                                     "replace as a whole: that would delete it; move it out or choose another "
                                     "output_dir")
        if not overwrite:
            raise OutputDirError(f"output_dir {str(out)!r} is not empty (set overwrite=true to replace it)")
        if not (out / marker).is_file():
            raise OutputDirError(f"output_dir {str(out)!r} is not empty and holds no {marker} (not an earlier "
                                 "output of this tool): refusing to replace it; choose another output_dir")
        if listed_in is not None:
            foreign = _foreign_entries(out, _listed_outputs(out, marker, listed_in, legacy))
            if foreign:
                shown = ", ".join(repr(f) for f in foreign[:5]) + (f" and {len(foreign) - 5} more"
                                                                    if len(foreign) > 5 else "")
                entries = "1 entry" if len(foreign) == 1 else f"{len(foreign)} entries"
                raise OutputDirError(f"output_dir {str(out)!r} holds {entries} "
                                     f"the earlier run did not write ({shown}; its {marker} lists what it wrote): "
                                     "refusing to replace it, that would delete them; move them out or choose "
                                     "another output_dir")
    check_writable(out)
    return out


@contextmanager
def staged_directory(out: str | os.PathLike, marker: str, overwrite: bool = True,
                     owned: bool = False, listed_in: str | None = None,
                     inputs: Mapping[str, str | os.PathLike | None] | None = None,
                     legacy: re.Pattern | None = None) -> Iterator[Path]:
    """Yield a temporary directory; on success it becomes ``out`` (write ``marker`` in it), on error it goes.

    ``owned``: first remove what killed runs into ``out`` left behind (:func:`remove_stale_staging`), and
    keep an owner record (:data:`OWNER_FILE`: this process and host) in the temporary directory while it
    is written (it is removed before the swap; callers listing the tree must skip it), so that a later
    run can remove the tree if this process is killed. ``listed_in``, ``inputs``, ``legacy``:
    :func:`check_output_dir`'s.
    """
    if owned:
        remove_stale_staging(out)
    out = check_output_dir(out, marker, overwrite, listed_in, inputs, legacy)
    out.parent.mkdir(parents=True, exist_ok=True)
    with _terminate_as_exit():  # SIGTERM while it is written: the staged tree is removed (exit status 143)
        yield from _staged(out, marker, owned)


def _staged(out: Path, marker: str, owned: bool) -> Iterator[Path]:
    """:func:`staged_directory`'s work once ``out`` is checked."""
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.parent))
    os.chmod(tmp, 0o777 & ~current_umask())  # the finished directory gets a plain mkdir's mode, not 0700
    try:
        if owned:
            write_json_atomic(tmp / OWNER_FILE, owner_record())
        yield tmp
        if not (tmp / marker).is_file():
            raise RuntimeError(f"staged output misses its marker file {marker}")
        swap_into_place(tmp, out, owned=owned)
    except BaseException as exc:
        if owned:
            try:
                _remove_owned_tree(tmp)
            except OSError:
                shutil.rmtree(tmp, ignore_errors=True)
        else:
            shutil.rmtree(tmp, ignore_errors=True)
        if is_disk_full(exc):  # name the output, not the staged file; the earlier output is untouched
            where = Path(getattr(exc, "filename", None) or out)
            name = where.relative_to(tmp).as_posix() if tmp in where.parents else None
            raise DiskFullError(exc.errno, f"the disk is full: could not write output_dir {str(out)!r}"
                                           + (f" ({name})" if name else "")
                                           + "; nothing half-written is left and an earlier output there is "
                                             "unchanged; free some space and try again", str(out)) from exc
        raise


# -- owner records of staged trees: telling a killed run's leftovers from a live run's ---------------------

#: The owner record (JSON: pid, host, process start time) in a staged tree while its run writes it.
OWNER_FILE = ".sdn3d-owner.json"


def _proc_stat(pid: int) -> tuple[str, int] | None:
    """``(state, start time in clock ticks after boot)`` of ``pid`` from ``/proc`` (Linux), or None."""
    try:
        text = Path(f"/proc/{int(pid)}/stat").read_text()
        fields = text.rpartition(")")[2].split()  # the command name may hold spaces and parentheses
        return fields[0], int(fields[19])
    except (OSError, IndexError, ValueError):
        return None


def process_alive(pid: int, start: int | None = None) -> bool:
    """Whether process ``pid`` runs on this machine (a zombie does not).

    Args:
        start: the start time :func:`owner_record` recorded for it; where ``/proc`` shows another start
            time, ``pid`` was reused by a later process and the recorded one is gone.
    """
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # it exists (another user's process)
        pass
    except (OSError, OverflowError):
        return False
    stat = _proc_stat(pid)
    if stat is not None:
        state, started = stat
        if state in ("Z", "X", "x") or (start is not None and started != start):
            return False
    return True


def owner_record() -> dict:
    """Who writes a staged tree: this process (pid and start time) on this host."""
    stat = _proc_stat(os.getpid())
    return {"pid": os.getpid(), "host": socket.gethostname(), "start": stat[1] if stat else None}


def _owner_gone(tree: Path) -> bool:
    """True only if ``tree`` holds a readable owner record naming a process of this host that has ended."""
    try:
        record = json.loads((tree / OWNER_FILE).read_text())
    except (OSError, ValueError):
        return False
    return _record_gone(record)


def _record_gone(record: Any) -> bool:
    """True only if ``record`` (:func:`owner_record`'s) names a process of this host that has ended."""
    if not isinstance(record, dict) or record.get("host") != socket.gethostname():
        return False
    pid, start = record.get("pid"), record.get("start")
    if not isinstance(pid, int) or isinstance(pid, bool) or not (start is None or isinstance(start, int)):
        return False
    return not process_alive(pid, start)


def _remove_owned_tree(tree: Path) -> None:
    """Delete a staged tree, its owner record last: a run killed meanwhile leaves a tree still marked as its."""
    for child in list(tree.iterdir()):
        if child.name == OWNER_FILE:
            continue
        if child.is_dir() and not child.is_symlink():
            shutil.rmtree(child)
        else:
            child.unlink()
    shutil.rmtree(tree)


def remove_stale_staging(out: str | os.PathLike) -> list[Path]:
    """Remove what killed runs into ``out`` left beside it; returns the trees removed.

    Candidates are ``.<name>.partial-*`` (a staged tree being written) and ``.<name>.old-*`` (the previous
    ``out`` being deleted) next to ``out``. Only trees whose owner record (:data:`OWNER_FILE`) names a
    process of this host that has ended are touched: a live run's trees, another host's, and trees
    without a record (another tool's, or older versions') are left alone. An ``.old-*`` tree whose run
    died between its two renames, ``out`` missing, is moved back to ``out`` (the previous result), not
    deleted.
    """
    log = logging.getLogger(__name__)
    out = Path(out).expanduser().resolve()
    if not out.parent.is_dir() or not out.name:
        return []
    try:
        siblings = sorted(out.parent.iterdir())
    except OSError:  # unreadable: the run itself fails on it with a clearer error
        return []
    removed = []
    for kind in ("partial", "old"):
        prefix = f".{out.name}.{kind}-"
        for tree in (p for p in siblings if p.name.startswith(prefix)):
            try:
                if tree.is_symlink() or not tree.is_dir() or not _owner_gone(tree):
                    continue
                if kind == "old" and (tree / "tree").is_dir() and not os.path.lexists(out):
                    os.rename(tree / "tree", out)
                    log.warning("restored %s from %s (a run was killed while replacing it)", out, tree.name)
                _remove_owned_tree(tree)
            except OSError as exc:  # e.g. another run removing it at the same time: not this run's problem
                log.warning("could not remove the stale staging tree %s: %s", tree, exc)
                continue
            log.info("removed %s, left by a killed run", tree)
            removed.append(tree)
    return removed


# -- one writer per output: lock files ----------------------------------------------------------------------


class BusyError(OutputDirError):
    """Another live process is writing the same output (its lock file names it)."""


def _describe_holder(record: Any) -> str:
    if not isinstance(record, dict):
        return "an unreadable lock record"
    return f"pid {record.get('pid')} on host {record.get('host')!r}, started {record.get('started', '?')}"


@contextmanager
def writer_lock(lock: str | os.PathLike, what: str) -> Iterator[Path]:
    """Hold the lock file ``lock`` (JSON: :func:`owner_record` and the start time) while the block runs: one writer
    per output (``what`` names the output in messages). A lock whose owner has ended on this host (a killed run)
    is stale: it is replaced, with a warning. The file is created complete and exclusively (a finished temporary
    file hard-linked onto the name), and removed at the end if it is still this process's.

    Raises:
        BusyError: the lock is held by a live process, another host's or one whose record can not be read; the
            message names the holder, the lock file and what to do.
    """
    from datetime import datetime

    lock = Path(lock).expanduser().absolute()
    lock.parent.mkdir(parents=True, exist_ok=True)
    record = owner_record() | {"started": datetime.now().astimezone().isoformat(timespec="seconds"),
                               "what": str(what)}
    fd, tmp = tempfile.mkstemp(prefix=f".{lock.name}.", suffix=".tmp", dir=lock.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            json.dump(record, handle)
        for _ in range(3):
            try:
                os.link(tmp, lock)
                break
            except FileExistsError:
                try:
                    holder = json.loads(lock.read_text(encoding="utf-8"))
                except FileNotFoundError:  # released meanwhile: try again
                    continue
                except (OSError, ValueError):
                    holder = None
                if holder is None or not _record_gone(holder):
                    raise BusyError(f"{what} is being written by another sdn3d process ({_describe_holder(holder)}; "
                                    f"lock file {str(lock)!r}): wait for it to finish or choose another output; if "
                                    "no such process runs any more, delete the lock file") from None
                logging.getLogger(__name__).warning("removing the stale lock %s of %s (that process has ended)", lock,
                                                    _describe_holder(holder))
                lock.unlink(missing_ok=True)
        else:
            raise BusyError(f"{what}: could not take the lock file {str(lock)!r} (it keeps changing hands); "
                            "try again")
    finally:
        os.unlink(tmp)
    try:
        yield lock
    finally:
        try:
            if json.loads(lock.read_text(encoding="utf-8")) == record:
                lock.unlink()
        except (OSError, ValueError):
            pass
