"""Training runs on disk: the checkpoints that ``sdn3d-train`` summaries record, and their inference exports.

A run directory holds ``summary.json`` (branch, status, ``best_ckpt`` / ``last_ckpt``, finish time);
:func:`find_run_checkpoints` finds, under any directory (the demo's ``<out>/runs/<branch>/``, one run, or a
training root ``<branch>/<time>/``), each branch's latest successful run and its checkpoint, and the inference
export made from that checkpoint (``checkpoints/inference.pt``, :mod:`sdn3d.inference_export`) when there is
one; :func:`export_checkpoint` writes such an export (``sdn3d-train`` at the end of a run,
``sdn3d-export-weights``); :func:`quality_warnings` says when the semantic branch's recorded validation quality
is too low to trust.
"""

from __future__ import annotations

import json
import logging
import os
import sys
from collections.abc import Mapping, Sequence
from datetime import datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sdn3d.errors import InputError, UserInputError
from sdn3d.labels import VEHICLE_CLASS_NAMES

if TYPE_CHECKING:
    from sdn3d.io import TorchFiles

__all__ = ["BRANCHES", "find_run_checkpoints", "given_checkpoints", "checkpoints_from_run", "report_checkpoints",
           "export_checkpoint", "export_run_checkpoint", "semantic_summary", "quality_warnings", "recorded_pq",
           "trained_data", "from_trained_data", "MIN_VEHICLE_PQ", "MIN_MIOU", "MAX_PROPOSAL_COVER"]

log = logging.getLogger(__name__)

BRANCHES = ("semantic", "geometric", "textural")


def _finished(summary: dict, path: Path) -> float:
    """When the run ended (its ``finished`` stamp, else the summary file's time), as a POSIX time."""
    try:
        stamp = datetime.fromisoformat(str(summary.get("finished")))
        return stamp.timestamp()
    except (TypeError, ValueError):
        return path.stat().st_mtime


def _in_run_dir(recorded: str, summary: dict, path: Path) -> Path:
    """A file a run's summary (at ``path``) records, where it lies in the run directory the summary is in now.

    ``sdn3d-train`` records absolute paths, under the ``run_dir`` it trained in; a run copied or moved elsewhere keeps
    them. A recorded file under the recorded ``run_dir`` is taken from the same place under the summary's own
    directory (never from the place it was recorded at: that is another copy, or gone); a relative one is relative
    to the summary's directory; any other is taken as recorded.
    """
    file = Path(recorded).expanduser()
    if not file.is_absolute():
        return path.parent / file
    run_dir = summary.get("run_dir")
    if isinstance(run_dir, str) and run_dir:
        try:
            return path.parent / file.relative_to(run_dir)
        except ValueError:
            pass
    return file


def _summary_checkpoint(summary: dict, path: Path) -> tuple[str, Path] | None:
    """``('best' | 'last', file)`` of a run's summary: its best checkpoint, else its last, each looked for in the
    summary's own run directory (:func:`_in_run_dir`: a copied or moved run serves its own files), then in
    ``<summary dir>/checkpoints/`` by name. A recorded best checkpoint that is missing is warned about, naming it,
    before the last one is used (other weights than those the run's figures were tested with)."""
    missing = None
    for which in ("best", "last"):
        recorded = summary.get(f"{which}_ckpt")
        if not isinstance(recorded, str) or not recorded:
            continue
        for candidate in (_in_run_dir(recorded, summary, path), path.parent / "checkpoints" / Path(recorded).name):
            if candidate.is_file():
                if missing is not None:
                    log.warning("run summary %s records the best checkpoint %s, which is missing: using its last "
                                "checkpoint %s instead (the weights at the end of training, not the ones its figures "
                                "were tested with); restore the file, or name a checkpoint with checkpoints.<branch>=",
                                path, missing, candidate.resolve())
                return which, candidate.resolve()
        missing = _in_run_dir(recorded, summary, path)
    return None


def _matching_export(checkpoint: Path, files: TorchFiles | None = None) -> Path | None:
    """The inference export beside ``checkpoint`` (``<its dir>/inference.pt``) if it was made from this very file
    (:func:`sdn3d.inference_export.export_matches`, its source record read through ``files`` where given); a stale or
    unreadable one is logged and passed over."""
    from sdn3d.inference_export import EXPORT_NAME, export_matches, read_export_source

    export = checkpoint.parent / EXPORT_NAME
    if not export.is_file():
        return None
    try:
        source = read_export_source(export, files)
    except UserInputError as exc:
        log.warning("ignoring %s: %s", export, exc)
        return None
    if export_matches(source, checkpoint):
        return export
    log.warning("ignoring %s: it was made from %s (sha256 %s...), not from %s as it is now; loading the checkpoint "
                "(export it again: sdn3d-export-weights %s)", export, source.get("file"),
                str(source.get("sha256"))[:12], checkpoint.name, checkpoint)
    return None


def find_run_checkpoints(run: str | Path, files: TorchFiles | None = None) -> tuple[dict[str, dict], dict[str, str]]:
    """The branches' checkpoints recorded by the ``sdn3d-train`` summaries under ``run``; the inference exports
    beside them are read through ``files`` where given (:class:`~sdn3d.io.TorchFiles`: loading their weights then
    takes over what was read).

    Returns ``(chosen, missing)``: per branch found, ``{'path', 'checkpoint', 'export', 'which' ('best' |
    'last'), 'summary', 'finished'}`` of its latest run with status ok and a checkpoint on disk (``checkpoint``;
    ``path``, the file to load, is its inference export when one made from it lies beside it, ``export``
    True, else the checkpoint itself); per branch without one, why.

    Every path is taken from the run directories under ``run`` (:func:`_in_run_dir`), so a copied or moved tree of
    runs serves its own files.

    Raises:
        InputError: ``run`` is not a directory, holds no branch summary, or holds a ``summary.json`` that can not be
            read (naming it: it may be a branch's newest run).
    """
    root = Path(str(run)).expanduser()
    if not root.exists():
        raise InputError(f"run {str(root)!r} does not exist (give a training output directory, e.g. "
                         f"run=outputs/demo or run=outputs/train)")
    if not root.is_dir():
        raise InputError(f"run {str(root)!r} is not a directory (give a training output directory, e.g. "
                         f"run=outputs/demo)")
    runs: dict[str, list[tuple[Path, dict]]] = {b: [] for b in BRANCHES}
    summaries = sorted(root.rglob("summary.json"))
    for path in summaries:
        try:
            summary = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            # It may be a branch's newest run: choosing an older one instead would be a silent wrong answer.
            raise InputError(f"run summary {str(path)!r} is unreadable ({type(exc).__name__}: "
                             f"{str(exc).splitlines()[0][:120] if str(exc) else ''}): it may record a branch's newest "
                             "run, so no run is chosen; restore or delete that file, or give run= one run "
                             "directory") from exc
        if isinstance(summary, dict) and summary.get("branch") in runs:
            runs[summary["branch"]].append((path, summary))
    if not any(runs.values()):
        seen = f" ({len(summaries)} summary.json file(s), none from sdn3d-train)" if summaries else ""
        raise InputError(f"run {str(root)!r} holds no training summary{seen}: expected sdn3d-train's "
                         f"summary.json files (<run>/runs/<branch>/, <run>/ or <run>/<branch>/<time>/)")
    chosen: dict[str, dict] = {}
    missing: dict[str, str] = {}
    for branch, found in runs.items():
        usable = []
        for path, summary in found:
            ckpt = _summary_checkpoint(summary, path) if summary.get("status") == "ok" else None
            if ckpt is not None:
                usable.append((_finished(summary, path), str(path), ckpt))
        if usable:
            finished, path, (which, file) = max(usable)
            export = _matching_export(file, files)
            chosen[branch] = {"path": str(export or file), "checkpoint": str(file), "export": export is not None,
                              "which": which, "summary": path,
                              "finished": datetime.fromtimestamp(finished).astimezone().isoformat(timespec="seconds")}
        elif not found:
            missing[branch] = "no run"
        else:
            statuses = sorted({str(s.get("status")) for _, s in found})
            missing[branch] = (f"{len(found)} run(s) (status {', '.join(statuses)}) but none ok with a checkpoint "
                               f"on disk")
    return chosen, missing


def given_checkpoints(checkpoints: Mapping[str, Any] | None) -> dict[str, dict | None]:
    """Per branch of :data:`BRANCHES`, ``{'path', 'from': 'checkpoints.<branch>'}`` of the file a command's
    ``checkpoints.<branch>=`` names, None where it names none."""
    checkpoints = checkpoints or {}
    return {b: None if checkpoints.get(b) is None else {"path": str(checkpoints.get(b)), "from": f"checkpoints.{b}"}
            for b in BRANCHES}


def checkpoints_from_run(run: str | Path, checkpoints: Mapping[str, Any] | None, needed: Sequence[str], tool: str,
                         purpose: str, files: TorchFiles | None = None) -> dict[str, dict | None]:
    """A command's ``run=<dir>``: per branch the file it loads, printed on stderr (:func:`report_checkpoints`).

    ``checkpoints.<branch>`` given explicitly wins (:func:`given_checkpoints`); every other branch takes the run's
    choice (:func:`find_run_checkpoints`): ``{'path', 'from' (its summary.json), 'which', 'finished',
    'checkpoint', 'export'}``; a branch neither gives is None.

    Args:
        run: the training output directory (a demo's ``outputs/demo``, one run, a training root).
        checkpoints: the command's ``checkpoints`` settings (``{branch: file or None}``).
        needed: the branches the command can not do without.
        tool: the command's name for messages (``sdn3d-edit``, ``sdn3d-bench``).
        purpose: what needs them, for the error (``the edit``, ``the benchmark``).
        files: what reads the run's inference exports (:func:`find_run_checkpoints`).

    Raises:
        InputError: a bad ``run`` (:func:`find_run_checkpoints`), or ``run`` lacks a needed branch that
            ``checkpoints`` does not give (naming what it found and how to give the file).
    """
    result = given_checkpoints(checkpoints)
    chosen, missing = find_run_checkpoints(run, files)
    lacking = [b for b in needed if result[b] is None and b in missing]
    if lacking:
        found = "; ".join(f"{b}: {Path(c['path']).name} ({c['which']})" for b, c in chosen.items()) or "nothing usable"
        why = "; ".join(f"{b}: {missing[b]}" for b in lacking)
        raise InputError(f"run {str(run)!r} lacks the {' and '.join(lacking)} branch {purpose} needs ({why}); "
                         f"found {found}. Train it, or give checkpoints.{lacking[0]}=<file>")
    for branch, info in chosen.items():
        if result[branch] is None:
            result[branch] = {"path": info["path"], "from": info["summary"], "which": info["which"],
                              "finished": info["finished"], "checkpoint": info["checkpoint"], "export": info["export"]}
    report_checkpoints(result, tool)
    return result


def report_checkpoints(checkpoints: Mapping[str, dict | None], tool: str) -> None:
    """Print on stderr, one line per branch, the file each branch loads (``<tool>: <branch> checkpoint: ...``):
    given, the run's (which checkpoint, an inference export of it or not, when its run finished), or none."""
    for branch in BRANCHES:
        info = checkpoints.get(branch)
        export = "inference export of the " if info is not None and info.get("export") else ""
        how = ("none" if info is None else f"{info['path']} (given)" if "which" not in info
               else f"{info['path']} ({export}{info['which']} checkpoint of the run finished {info['finished']})")
        print(f"{tool}: {branch} checkpoint: {how}", file=sys.stderr)


def export_checkpoint(checkpoint: str | os.PathLike, out: str | os.PathLike | None = None,
                      overwrite: bool = False) -> Path:
    """Write the inference export of a branch's Lightning checkpoint (:mod:`sdn3d.inference_export`); returns it.

    ``out`` None: ``inference.pt`` beside the checkpoint (an earlier export there is replaced). An existing
    ``out`` is replaced only with ``overwrite``, a training checkpoint never
    (:func:`sdn3d.inference_export.check_export_target`, checked before the checkpoint is read). A geometric
    checkpoint's export records its run's crop size and margin (:func:`sdn3d.models.geometric_crop_settings`), a
    semantic checkpoint's its training frame size (:func:`sdn3d.models.semantic_trained_size`), when the run's
    ``config.yaml`` says them.

    Raises:
        UserInputError: naming the file: the checkpoint is missing, unreadable or holds no branch's weights,
            or its run's config is unreadable; ``out`` may not be written.
    """
    from sdn3d.inference_export import EXPORT_NAME, check_export_target, write_inference_export
    from sdn3d.io import checkpoint_branch, load_lightning_checkpoint
    from sdn3d.models import geometric_crop_settings, semantic_trained_size

    path = Path(checkpoint).expanduser()
    check_export_target(path.parent / EXPORT_NAME if out is None else out, path, overwrite, default=out is None)
    ckpt = load_lightning_checkpoint(path)
    settings = {}
    if checkpoint_branch(ckpt) == "geometric":
        found = geometric_crop_settings(path)
        if found is not None:
            settings = {"crop_size": found[0], "margin": found[1]}
    elif checkpoint_branch(ckpt) == "semantic":
        trained = semantic_trained_size(path)
        if trained is not None:
            settings = {"image_size": list(trained)}
    return write_inference_export(path, ckpt, out, settings, overwrite)


def export_run_checkpoint(summary_file: str | os.PathLike) -> Path | None:
    """Write the inference export of the checkpoint a run's ``summary.json`` selects (its best, else its last:
    the one ``run=`` loads) beside it (:func:`export_checkpoint`); returns it, or None without a checkpoint or for
    the Deep3DBox baseline (``ablation: deep3dbox``, Table 2 only).

    Raises:
        UserInputError: the summary is not readable JSON, or :func:`export_checkpoint`'s errors.
    """
    path = Path(summary_file)
    try:
        summary = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise UserInputError(f"run summary {str(path)!r} is not readable JSON ({exc})") from exc
    if isinstance(summary, dict) and summary.get("ablation") == "deep3dbox":
        return None  # the Table 2 baseline cannot de-render: nothing to export for inference
    selected = _summary_checkpoint(summary, path) if isinstance(summary, dict) else None
    return None if selected is None else export_checkpoint(selected[1])


# -- what a run recorded: is the semantic branch good enough to trust? --------------------------------

#: Below these recorded validation figures of the semantic branch its proposals are not to be trusted: the share of
#: vehicles over the paper's 256 pixels that its proposals find (IoU >= 0.5) and the share of its proposals that are
#: vehicles (``val/proposal_recall`` and ``val/proposal_precision``, what editing needs); where a run recorded no
#: such figures, its vehicle PQ, else its mIoU.
MIN_PROPOSAL_RECALL = 0.5
MIN_PROPOSAL_PRECISION = 0.5
MIN_VEHICLE_PQ = 0.3
MIN_MIOU = 0.3
#: Proposals covering more of the frame than this are not a street's vehicles.
MAX_PROPOSAL_COVER = 0.5


def semantic_summary(info: dict | None) -> Path | None:
    """The ``summary.json`` of the semantic branch's run: the one ``run=`` chose it from, else
    ``<checkpoint dir>/../summary.json`` (``sdn3d-train``'s ``<run>/checkpoints/<file>.ckpt``); None: none."""
    if info is None:
        return None
    path = Path(str(info["from"])) if "which" in info else Path(str(info["path"])).expanduser().parent.parent / \
        "summary.json"
    return path if path.is_file() else None


def _number(metrics: Mapping[str, Any], key: str) -> float | None:
    value = metrics.get(key)
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and value == value
    return float(value) if ok else None


def recorded_pq(metrics: Mapping[str, Any] | None, stage: str = "val") -> tuple[str, float] | None:
    """The semantic branch's recorded panoptic quality on a part (``stage``: ``val`` or ``test``) as ``(name,
    value)``: the mean over its vehicle classes (``<stage>/pq_<class>``, the class in any case: ``sdn3d-train``
    writes ``val/pq_Car``) named ``vehicle PQ``, else ``<stage>/pq``; None: not recorded (or not a number)."""
    metrics = metrics if isinstance(metrics, Mapping) else {}
    prefix = f"{stage}/pq_"
    vehicles = [v for k in metrics if k.lower().startswith(prefix) and k[len(prefix):].lower() in VEHICLE_CLASS_NAMES
                for v in [_number(metrics, k)] if v is not None]
    if vehicles:
        return "vehicle PQ", sum(vehicles) / len(vehicles)
    pq = _number(metrics, f"{stage}/pq")
    return None if pq is None else (f"{stage}/pq", pq)


def recorded_proposals(metrics: Mapping[str, Any] | None, stage: str = "val") -> tuple[float, float] | None:
    """``(recall, precision)`` of the semantic branch's proposals on a part as its run recorded them
    (``<stage>/proposal_recall``, ``<stage>/proposal_precision``); None where either is not recorded."""
    metrics = metrics if isinstance(metrics, Mapping) else {}
    recall, precision = _number(metrics, f"{stage}/proposal_recall"), _number(metrics, f"{stage}/proposal_precision")
    return None if recall is None or precision is None else (recall, precision)


def proposals_trusted(proposals: tuple[float, float]) -> bool:
    """Whether recorded ``(recall, precision)`` reach :data:`MIN_PROPOSAL_RECALL` and :data:`MIN_PROPOSAL_PRECISION`."""
    return proposals[0] >= MIN_PROPOSAL_RECALL and proposals[1] >= MIN_PROPOSAL_PRECISION


def trained_data(summary_file: str | os.PathLike | None) -> dict | None:
    """The data a run trained on, from the ``config.yaml`` beside its ``summary.json`` (``sdn3d-train`` writes
    both): ``{"kind": data.kind, "root": data.root}``, a relative root resolved against the working directory
    (``sdn3d-train`` resolves it against its launch directory); None where not recorded or not readable."""
    import yaml

    from sdn3d.io import yaml_loader

    if not summary_file:
        return None
    config = Path(summary_file).parent / "config.yaml"
    try:
        data = (yaml.load(config.read_text(encoding="utf-8"), Loader=yaml_loader()) or {}).get("data")  # noqa: S506
    except (OSError, UnicodeDecodeError, yaml.YAMLError, AttributeError):
        return None
    root = data.get("root") if isinstance(data, dict) else None
    if not isinstance(root, str) or not root or "${" in root:
        return None
    return {"kind": str(data.get("kind", "")), "root": str(Path(root).expanduser().resolve())}


def from_trained_data(trained: Mapping[str, Any] | None, input_path: str | os.PathLike | None) -> bool | None:
    """Whether the input (an image file, or the root of the dataset a frame was read from) lies in the data root
    a run trained on (:func:`trained_data`); None where either is unknown. A frame of another part of that data
    (validation, test) counts as from it: what matters is that the weights were trained on that data."""
    if trained is None or not input_path:
        return None
    path, root = Path(input_path).expanduser().resolve(), Path(str(trained["root"]))
    return path == root or root in path.parents


def _run_label(where: str) -> str:
    """``run <dir> (experiment <name>, <n> training steps)`` for a run's ``summary.json`` path; else ``where``."""
    path = Path(where) if where else None
    if path is None or not path.is_file():
        return where or "the semantic run"
    try:
        summary = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        summary = None
    facts = []
    if isinstance(summary, dict):
        if summary.get("experiment"):
            facts.append(f"experiment {summary['experiment']}")
        if isinstance(summary.get("global_step"), int):
            facts.append(f"{summary['global_step']} training steps")
    return f"run {path.parent}" + (f" ({', '.join(facts)})" if facts else "")


def quality_warnings(metrics: dict | None, coverage: float | None, where: str = "the semantic run",
                     input_path: str | os.PathLike | None = None) -> list[str]:
    """Warnings on the semantic branch's proposals: its recorded validation quality (proposal recall and precision,
    :func:`recorded_proposals`, under :data:`MIN_PROPOSAL_RECALL` / :data:`MIN_PROPOSAL_PRECISION`; a run that
    recorded none: vehicle PQ, else ``val/pq``, else ``val/miou``, :func:`recorded_pq`, under :data:`MIN_VEHICLE_PQ`
    / :data:`MIN_MIOU`), or proposals
    covering more than :data:`MAX_PROPOSAL_COVER` of the frame (``coverage``, a fraction; None: not known).

    ``where``: the run's ``summary.json`` (each warning names the run, its experiment and steps, and the figure);
    ``input_path``: the image file edited, or the root of the dataset its frame came from (None: not known). Only
    where the input is not from the data the run trained on (:func:`trained_data`, :func:`from_trained_data`) does a
    warning say that real photos need branches trained on Virtual KITTI or Cityscapes; on a frame of that data a low
    figure is the branch's own weakness, and the warning says so."""
    out = []
    metrics = metrics if isinstance(metrics, dict) else {}
    proposals = recorded_proposals(metrics)
    pq = recorded_pq(metrics)
    miou = _number(metrics, "val/miou")
    low = None
    if proposals is not None:
        if not proposals_trusted(proposals):
            low = (f"recorded proposal recall is {proposals[0]:.3f} and precision {proposals[1]:.3f} (each must reach "
                   f"{MIN_PROPOSAL_RECALL}, {where})")
    elif pq is not None and pq[1] < MIN_VEHICLE_PQ:
        low = f"recorded {pq[0]} is {pq[1]:.3f} (< {MIN_VEHICLE_PQ}, {where})"
    elif pq is None and miou is not None and miou < MIN_MIOU:
        low = f"recorded val/miou is {miou:.3f} (< {MIN_MIOU}, {where})"
    covers = coverage is not None and coverage > MAX_PROPOSAL_COVER
    cause = _warning_cause(where, input_path) if low is not None or covers else ""
    if low is not None:
        out.append(f"the semantic branch's {low}: {_run_label(where)} scored it on its validation part; its "
                   f"object proposals are likely wrong; {cause}")
    if covers:
        out.append(f"the semantic branch's object proposals cover {100 * coverage:.0f} % of the frame "
                   f"(> {100 * MAX_PROPOSAL_COVER:.0f} %): not plausible vehicles ({_run_label(where)}); {cause}")
    return out


def _warning_cause(where: str, input_path: str | os.PathLike | None) -> str:
    """What :func:`quality_warnings` tells the user to do about a weak semantic branch, by whether the input is from
    the data the run trained on. Only built for a warning: it reads the run's ``config.yaml``
    (:func:`trained_data`); built before knowing whether a warning is due, it cost each ``sdn3d-edit`` call two
    reads of that file it did not use."""
    trained = trained_data(where) if where else None
    source = from_trained_data(trained, input_path)
    boxes = "name the cars by box (`objects: [{box: [x0, y0, x1, y1], class: Car}]` with proposals=boxes)"
    if source is False:
        return (f"this input is not from the data the run trained on ({trained['kind']} at {trained['root']}): real "
                f"photos need branches trained on Virtual KITTI or Cityscapes (docs/TRAINING.md), or {boxes}")
    if source is True:
        return (f"this input is from the data the run trained on ({trained['root']}), so the branch itself is too "
                f"weak: train it longer, or {boxes}")
    return f"train it longer, or {boxes}"
