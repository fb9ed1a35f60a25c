"""``sdn3d-table2``: the paper's Table 2 (3D attribute prediction, geometric-branch ablations).

    sdn3d-table2 --summary outputs/train/summary.jsonl --out outputs/tables
    sdn3d-table2 --multirun outputs/multirun/geometric --data-root /work/data/synth
    sdn3d-table2 --summary outputs/train/summary.jsonl --deep3dbox oracle --data-root /work/data/synth

Inputs: ``summary.jsonl`` files that ``sdn3d-train`` appends one JSON object per finished run to,
and/or run / multirun directories searched for the ``summary.json`` each run writes. Only
geometric-branch runs with ``status == "ok"`` count; per ablation the latest (``finished``) wins.

Rows (paper order): the Deep3DBox-style baseline, w/o reprojection (``no_reproj``), quaternion
(``full_quaternion``), w/o tau (``no_tau``), single CAD (``single_cad``), full model (``full``).
Columns: orientation similarity (higher is better), distance, scale and reprojection errors
(lower is better), the run's ``test/...`` metrics. The Deep3DBox row is computed here: the full
model's yaw, dimensions and mesh on the test split, with the translation replaced by
:func:`sdn3d.geometric.deep3dbox.solve_translation` (``--deep3dbox oracle``: ground-truth yaw and
dimensions instead, needs no checkpoint).

Outputs ``<out>/table2.md`` and ``<out>/table2.json``, written atomically, only after every
input has been read and checked. Exit codes: 0 done; 2 bad input (unreadable or malformed
summary: the message names the file and line; outputs untouched); 1 the Deep3DBox evaluation failed.
"""

from __future__ import annotations

import argparse
import json
import math
import pickle  # torch.load raises pickle.UnpicklingError for a file that is not a checkpoint
import sys
from collections.abc import Iterable, Mapping, Sequence
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from sdn3d.cli._errors import run_cli
from sdn3d.errors import InputError, UserInputError
from sdn3d.io import write_json_atomic, write_text_atomic

__all__ = ["ROWS", "COLUMNS", "PAPER", "SummaryError", "load_runs", "latest_runs", "build_table",
           "render_markdown", "main"]

#: Table rows in the paper's order: (key, label); keys other than ``deep3dbox`` are ablation names.
ROWS = (
    ("deep3dbox", "Deep3DBox-style baseline (Mousavian et al.)"),
    ("no_reproj", "w/o reprojection"),
    ("full_quaternion", "quaternion (4-D)"),
    ("no_tau", "w/o tau (log distance)"),
    ("single_cad", "single CAD"),
    ("full", "full model"),
)
#: Columns: (metric key in the run summary, header, higher is better).
COLUMNS = (
    ("test/orientation_similarity", "Orientation similarity", True),
    ("test/distance_error", "Distance error", False),
    ("test/scale_error", "Scale error", False),
    ("test/reprojection_error", "Reprojection error", False),
)
#: The paper's numbers (3D-SDN, NeurIPS 2018, Table 2, Virtual KITTI). Only the full model's row is
#: transcribed here; the other rows are left out rather than quoted from memory.
PAPER: dict[str, dict[str, float]] = {
    "full": {"test/orientation_similarity": 0.987, "test/distance_error": 3.87e-2, "test/scale_error": 0.382,
             "test/reprojection_error": 3.37e-3},
}
_ORACLE_LABEL = "Deep3DBox-style, ground-truth yaw/dims (oracle)"


class SummaryError(UserInputError):
    """A summary file that cannot be read or is malformed (message names the file and line)."""


# --------------------------------------------------------------------------- reading runs
def _check_record(obj: Any, where: str) -> dict[str, Any]:
    if not isinstance(obj, dict):
        raise SummaryError(f"{where}: expected a JSON object, got {type(obj).__name__}")
    for key in ("branch", "metrics", "status"):
        if key not in obj:
            raise SummaryError(f"{where}: missing key {key!r}")
    if not isinstance(obj["metrics"], dict):
        raise SummaryError(f"{where}: 'metrics' must be an object, got {type(obj['metrics']).__name__}")
    for name, value in obj["metrics"].items():
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))):
            raise SummaryError(f"{where}: metric {name!r} must be a number, got {value!r}")
    if obj.get("ablation") is not None and not isinstance(obj["ablation"], str):
        raise SummaryError(f"{where}: 'ablation' must be a string or null, got {obj['ablation']!r}")
    if obj.get("finished") is not None:
        try:
            _finished(obj)
        except (TypeError, ValueError) as exc:
            raise SummaryError(f"{where}: 'finished' is not an ISO time: {obj['finished']!r}") from exc
    return {**obj, "_source": where}


def _finished(record: Mapping[str, Any]) -> datetime:
    value = record.get("finished")
    if value is None:
        return datetime.min.replace(tzinfo=timezone.utc)
    stamp = datetime.fromisoformat(str(value))
    return stamp if stamp.tzinfo else stamp.replace(tzinfo=timezone.utc)


def _read_jsonl(path: Path) -> list[dict[str, Any]]:
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SummaryError(f"{path}: cannot read: {exc}") from exc
    records = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip():
            continue
        try:
            obj = json.loads(line)
        except json.JSONDecodeError as exc:
            raise SummaryError(f"{path}:{number}: not valid JSON ({exc.msg} at column {exc.colno})") from exc
        records.append(_check_record(obj, f"{path}:{number}"))
    return records


def _read_summary_json(path: Path) -> dict[str, Any]:
    try:
        obj = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as exc:
        raise SummaryError(f"{path}: cannot read: {exc}") from exc
    except json.JSONDecodeError as exc:
        raise SummaryError(f"{path}:{exc.lineno}: not valid JSON ({exc.msg} at column {exc.colno})") from exc
    return _check_record(obj, f"{path}:1")


def load_runs(summaries: Iterable[str | Path] = (), run_dirs: Iterable[str | Path] = ()) -> list[dict[str, Any]]:
    """All run records of ``summaries`` (JSONL files) and of the ``summary.json`` files under ``run_dirs``.

    Each record gets a ``_source`` (``file:line``). Raises :class:`SummaryError` on the first bad file.
    """
    records: list[dict[str, Any]] = []
    for path in map(Path, summaries):
        if not path.is_file():
            raise SummaryError(f"{path}: summary file does not exist")
        records.extend(_read_jsonl(path))
    for root in map(Path, run_dirs):
        if not root.is_dir():
            raise SummaryError(f"{root}: run/multirun directory does not exist")
        records.extend(_read_summary_json(p) for p in sorted(root.rglob("summary.json")))
    return records


def latest_runs(records: Iterable[Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per ablation name: the latest successful geometric run (``finished``; later input wins ties).

    Geometric runs without an ablation name count as ``full`` (the default ablation). Ablations
    with only failed runs map to their latest failed run (its ``status`` says so).
    """
    best: dict[str, tuple[tuple[bool, datetime, int], dict[str, Any]]] = {}
    for order, record in enumerate(records):
        if record.get("branch") != "geometric":
            continue
        name = record.get("ablation") or "full"
        key = (record.get("status") == "ok", _finished(record), order)
        if name not in best or key > best[name][0]:
            best[name] = (key, dict(record))
    return {name: record for name, (_, record) in best.items()}


# --------------------------------------------------------------------------- table
def _number(value: Any) -> float | None:
    if value is None or isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def _source(record: Mapping[str, Any]) -> dict[str, Any]:
    return {k: record.get(k) for k in ("run_dir", "finished", "best_ckpt", "last_ckpt", "seed", "_source")}


def build_table(runs: Mapping[str, Mapping[str, Any]], deep3dbox: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The table as a JSON-ready dict.

    Args:
        runs: :func:`latest_runs` output.
        deep3dbox: the baseline row's metrics (:func:`sdn3d.geometric.deep3dbox.evaluate_deep3dbox`
            output plus optional ``label``, ``note`` and ``source``), or None (``not run``; an entry
            ``note`` explains why when given as ``{"note": ...}`` without metrics).
    """
    rows = []
    for key, label in ROWS:
        row: dict[str, Any] = {"key": key, "label": label, "status": "not run",
                               "metrics": {c: None for c, _, _ in COLUMNS},
                               "paper": {c: PAPER.get(key, {}).get(c) for c, _, _ in COLUMNS}}
        if key == "deep3dbox":
            if deep3dbox is not None:
                if any(c in deep3dbox for c, _, _ in COLUMNS):
                    row["status"] = "ok"
                    row["metrics"] = {c: _number(deep3dbox.get(c)) for c, _, _ in COLUMNS}
                    row["extra"] = {k: v for k, v in deep3dbox.items()
                                    if k not in row["metrics"] and k not in ("label", "note", "source")}
                row["label"] = deep3dbox.get("label", label)
                for k in ("note", "source"):
                    if deep3dbox.get(k) is not None:
                        row[k] = deep3dbox[k]
        elif key in runs:
            record = runs[key]
            row["status"] = "ok" if record.get("status") == "ok" else "failed"
            if row["status"] == "ok":
                row["metrics"] = {c: _number(record["metrics"].get(c)) for c, _, _ in COLUMNS}
            row["source"] = _source(record)
        rows.append(row)
    known = {k for k, _ in ROWS}
    return {
        "table": "3D-SDN Table 2: 3D attribute prediction (geometric branch)",
        "columns": [{"key": c, "header": h, "higher_is_better": up} for c, h, up in COLUMNS],
        "rows": rows,
        "ignored_ablations": sorted(set(runs) - known),
        "paper_note": "paper reference numbers: full model only (other rows not transcribed)",
    }


def _format(value: float | None) -> str:
    """The paper's style: ``0.987``, ``0.382``, ``3.87e-2``, ``3.37e-3``."""
    if value is None:
        return "n/a"
    if value == 0 or 0.1 <= abs(value) < 1000:
        return f"{value:.3f}"
    mantissa, exponent = f"{value:.2e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def render_markdown(table: Mapping[str, Any]) -> str:
    """Markdown of :func:`build_table`'s dict: measured columns, then the paper's."""
    columns = table["columns"]
    arrows = [f"{c['header']} {'↑' if c['higher_is_better'] else '↓'}" for c in columns]
    header = ["Method", *arrows, *(f"paper: {c['header']}" for c in columns)]
    lines = [f"# {table['table']}", "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    notes = []
    for row in table["rows"]:
        if row["status"] == "ok":
            cells = [_format(row["metrics"][c["key"]]) for c in columns]
        else:
            cells = [row["status"]] * len(columns)
        paper = [_format(row["paper"][c["key"]]) if row["paper"][c["key"]] is not None else "" for c in columns]
        lines.append("| " + " | ".join([row["label"], *cells, *paper]) + " |")
        source = row.get("source") or {}
        where = source.get("run_dir") or source.get("checkpoint")
        if where:
            notes.append(f"- {row['label']}: {where} (finished {source.get('finished') or '?'})")
        if row.get("note"):
            notes.append(f"- {row['label']}: {row['note']}")
    lines += ["", "Higher is better for orientation similarity, lower for the errors. Distance error: "
              "mean |log t - log t~| with t the distance to the box centre.", f"Paper column: {table['paper_note']}."]
    if table.get("ignored_ablations"):
        lines.append(f"Runs of other ablations not in the table: {', '.join(table['ignored_ablations'])}.")
    if notes:
        lines += ["", "Sources:", *notes]
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------- Deep3DBox row
def _datamodule_kwargs(full: Mapping[str, Any] | None, data_config: str | None, data_root: str | None,
                       batch_size: int) -> dict[str, Any]:
    """``GeometricDataModule`` arguments: ``--data-config`` (a run's ``config.yaml``, a config with a
    ``data`` node, or a ``conf/data`` file), else the full run's ``config.yaml``, else ``conf/data/synth.yaml``."""
    from omegaconf import OmegaConf

    if data_config is not None:
        cfg = OmegaConf.load(data_config)
    elif full is not None and full.get("run_dir") and (Path(str(full["run_dir"])) / "config.yaml").is_file():
        cfg = OmegaConf.load(Path(str(full["run_dir"])) / "config.yaml")
    else:
        from sdn3d.cli._config import config_dir

        cfg = OmegaConf.load(Path(config_dir()) / "data" / "synth.yaml")
    container = OmegaConf.to_container(cfg, resolve=True)
    if "datamodule" in container:
        kwargs = {k: v for k, v in container["datamodule"].items() if k != "_target_"}
    elif "data" in container:
        kwargs = {"data": container["data"]}
    else:
        kwargs = {"data": container}
    kwargs["data"] = dict(kwargs["data"])
    if data_root is not None:
        kwargs["data"]["root"] = data_root
    kwargs.update(batch_size=batch_size, num_workers=0)
    return kwargs


def _deep3dbox_row(args: argparse.Namespace, runs: Mapping[str, Mapping[str, Any]]) -> dict[str, Any]:
    """Metrics of the baseline row, or ``{"note": why not}``. Errors of the evaluation propagate."""
    if args.deep3dbox == "skip":
        return {"note": "not evaluated (--deep3dbox skip)"}
    full = runs.get("full")
    full = full if full is not None and full.get("status") == "ok" else None
    predictor, source = None, {}
    if args.deep3dbox == "auto":
        ckpt = full and (full.get("best_ckpt") or full.get("last_ckpt"))
        if not ckpt:
            return {"note": "needs a finished full-model run with a checkpoint (or --deep3dbox oracle)"}
        from sdn3d.geometric.predict import GeometricPredictor

        predictor = GeometricPredictor.from_checkpoint(ckpt, map_location=args.device)
        source = {"checkpoint": str(ckpt), "run_dir": full.get("run_dir"), "finished": full.get("finished")}
    from datamodules import GeometricDataModule
    from sdn3d.geometric.deep3dbox import evaluate_deep3dbox

    kwargs = _datamodule_kwargs(full, args.data_config, args.data_root, args.batch_size)
    datamodule = GeometricDataModule(**kwargs)
    datamodule.setup("test")
    metrics = evaluate_deep3dbox(predictor, datamodule.test_dataloader(), truncation=args.truncation)
    where = f"test split of {kwargs['data'].get('root')}"
    row: dict[str, Any] = {**metrics, "source": source or {"data": where}}
    if predictor is None:
        row["label"] = _ORACLE_LABEL
    row["note"] = (f"translation from the 2D box (192 upright corner assignments), {int(metrics['count'])} objects "
                   f"of the {where}" + (", sides cut by the image border dropped" if args.truncation else ""))
    return row


# --------------------------------------------------------------------------- CLI
def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="sdn3d-table2", description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--summary", action="append", default=[], metavar="JSONL",
                        help="summary.jsonl written by sdn3d-train (repeatable)")
    parser.add_argument("--multirun", action="append", default=[], metavar="DIR",
                        help="run or multirun directory searched for summary.json files (repeatable)")
    parser.add_argument("--out", default="outputs/tables", help="output directory (default: %(default)s)")
    parser.add_argument("--deep3dbox", choices=("auto", "oracle", "skip"), default="auto",
                        help="baseline row: auto = full model's yaw/dims (needs its checkpoint), oracle = "
                             "ground-truth yaw/dims, skip = not run (default: %(default)s)")
    parser.add_argument("--data-config", default=None,
                        help="data for the baseline: a run's config.yaml or a conf/data file (default: the "
                             "full run's config.yaml, else conf/data/synth.yaml)")
    parser.add_argument("--data-root", default=None, help="override the dataset root of that config")
    parser.add_argument("--batch-size", type=int, default=64)
    parser.add_argument("--device", default="cpu", help="device of the predictor (default: %(default)s)")
    parser.add_argument("--truncation", action="store_true",
                        help="baseline: drop the box sides cut by the image border (default: plain Deep3DBox)")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # argparse exits on --help and on bad usage; keep main's int contract
        return int(exc.code or 0)
    return run_cli("table2", _main, args)


def _check_args(args: argparse.Namespace) -> None:
    if not args.summary and not args.multirun:
        raise InputError("give at least one --summary FILE or --multirun DIR")
    if args.batch_size <= 0:
        raise InputError(f"--batch-size must be positive, got {args.batch_size}")


def _main(args: argparse.Namespace) -> int:
    _check_args(args)
    runs = latest_runs(load_runs(args.summary, args.multirun))
    try:
        deep3dbox = _deep3dbox_row(args, runs)
    except (ValueError, OSError, RuntimeError, KeyError, ImportError, pickle.UnpicklingError) as exc:
        print(f"sdn3d-table2: Deep3DBox evaluation failed: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1
    table = build_table(runs, deep3dbox)
    out = Path(args.out)
    write_json_atomic(out / "table2.json", table)
    write_text_atomic(out / "table2.md", render_markdown(table))
    print(render_markdown(table), end="")
    print(f"wrote {out / 'table2.md'} and {out / 'table2.json'}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
