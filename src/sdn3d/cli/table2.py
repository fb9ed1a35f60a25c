"""``sdn3d-table2``: the paper's Table 2 (3D attribute prediction, geometric-branch ablations).

    sdn3d-table2 --summary outputs/train/summary.jsonl --out outputs/tables
    sdn3d-table2 --multirun outputs/multirun/geometric --experiment table2

Inputs: ``summary.jsonl`` files that ``sdn3d-train`` appends one JSON object per finished run to,
and/or run / multirun directories searched for the ``summary.json`` each run writes. Only
geometric-branch runs count, each row from its runs' ``test/...`` metrics.

Rows, the paper's six in its order: Mousavian et al. (Deep3DBox; runs of ``ablation=deep3dbox``, the
independent baseline ``lightning_modules.Deep3DBoxModule``), w/o L_reproj (``no_reproj``), w/o quaternion
constraint (``full_quaternion``), w/o normalized distance tau (``no_tau``), w/o MultiCAD and FFD
(``single_cad``), full (``full``; also runs without an ablation name). The reference columns hold the
paper's six rows. After them, rows beyond the paper's where they have runs (:data:`EXTRA_ROWS`: the full model
with the MultiBin orientation, ``full_multibin``, which the editing default trains).

Seeds: runs are grouped by experiment and ablation; each cell is the mean ± sample std over the group's
successful runs (``n`` runs; a re-run of the same seed and settings replaces the earlier one). Runs of one
group that differ in anything but the seed (their command-line overrides) are reported as a warning. One
experiment per table: ``--experiment``, by default the one of the latest successful run.

Columns, units in the headers: orientation similarity; distance error ``|log t - log t~|`` (x1e-2, as the
paper); scale error (m); the paper's reprojection error (x1e-3: hard silhouette, mismatching pixels over
the W x H frame, the working size read from the runs' ``config.yaml``) and, labelled, the soft crop mean
(the training loss, not the paper's figure). A second table sets the mesh accuracy beside its floors
(majority template of the training part, uniform 1/8), the identifiability ceiling and the selection regret.
Below them: every row paired with the full model by seed, where the reprojection error comes from, and how far
training over-fits (L_pred on the training part's last epoch against the test part's, and their ratio).

Outputs ``<out>/table2.md`` and ``<out>/table2.json``, written atomically, only after every
input has been read and checked. Exit codes: 0 done; 2 bad input (unreadable or malformed
summary: the message names the file and line; an unknown ``--experiment``; outputs untouched).
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from sdn3d.cli._errors import run_argparse_cli
from sdn3d.errors import InputError, UserInputError
from sdn3d.io import write_json_atomic, write_text_atomic

__all__ = ["ROWS", "EXTRA_ROWS", "Column", "ATTRIBUTE_COLUMNS", "MESH_COLUMNS", "PAPER", "SummaryError", "load_runs",
           "settings_of", "group_runs", "choose_experiment", "summarize", "build_table", "render_markdown", "main"]

#: Table rows in the paper's order: (key, label); each key is an ablation name (``conf/ablation``).
ROWS = (
    ("deep3dbox", "Mousavian et al. (Deep3DBox)"),
    ("no_reproj", "w/o L_reproj"),
    ("full_quaternion", "w/o quaternion constraint"),
    ("no_tau", "w/o normalized distance tau"),
    ("single_cad", "w/o MultiCAD and FFD"),
    ("full", "3D-SDN (full)"),
)
#: Rows beyond the paper's, shown after them when they have runs: (key, label).
EXTRA_ROWS = (
    ("full_multibin", "3D-SDN (full), MultiBin orientation (the editing default; not a paper row)"),
)


@dataclass(frozen=True)
class Column:
    """One column: the run-summary metric, its header (unit included), direction and display scale."""

    key: str
    header: str
    higher_is_better: bool | None  # None: a reference figure (floor, ceiling), no direction
    scale: float = 1.0  # the cell shows metric * scale
    decimals: int = 3
    short: str = ""  # header of the paper's column, where there is one


#: Table 2's columns; ``{frame}`` and ``{crop}`` are filled with the runs' frame (W x H) and crop sizes.
ATTRIBUTE_COLUMNS = (
    Column("test/orientation_similarity", "Orientation similarity", True, short="orientation"),
    Column("test/distance_error", "Distance error (x1e-2)", False, 1e2, 2, "distance (x1e-2)"),
    Column("test/scale_error", "Scale error (m)", False, short="scale (m)"),
    Column("test/reprojection_error_image", "Reprojection error (x1e-3; hard, per pixel of the {frame} frame)",
           False, 1e3, 2, "reprojection (x1e-3, per image pixel)"),
    Column("test/reprojection_error_crop_soft", "Soft crop mean ({crop}; training loss, not the paper's)",
           False, 1.0, 4),
)
#: The mesh choice against its floors and ceiling.
MESH_COLUMNS = (
    Column("test/mesh_accuracy", "Mesh accuracy", True),
    Column("test/mesh_majority_floor", "Floor: training majority", None),
    Column("test/mesh_uniform_floor", "Floor: uniform (1/8)", None),
    Column("test/mesh_identifiability_ceiling", "Ceiling: identifiable at true pose", None),
    Column("test/selection_regret", "Selection regret (soft L_reproj, crop)", False, 1.0, 4),
)
#: The paper's Table 2 (3D-SDN, NeurIPS 2018, Virtual KITTI), in the metrics' own units; its reprojection
#: error is per image pixel, our ``test/reprojection_error_image``.
PAPER: dict[str, dict[str, float]] = {
    key: dict(zip(("test/orientation_similarity", "test/distance_error", "test/scale_error",
                   "test/reprojection_error_image"), values, strict=True))
    for key, values in {
        "deep3dbox": (0.976, 4.41e-2, 0.391, 9.80e-3),
        "no_reproj": (0.980, 3.76e-2, 0.372, 9.54e-3),
        "full_quaternion": (0.970, 4.59e-2, 0.403, 7.58e-3),
        "no_tau": (0.979, 4.27e-2, 0.420, 6.42e-3),
        "single_cad": (0.984, 3.37e-2, 0.464, 4.60e-3),
        "full": (0.987, 3.87e-2, 0.382, 3.37e-3),
    }.items()
}
#: Where the full model's test reprojection error comes from (``test/decomposition/<name>``, logged by
#: ``GeometricModule`` at test): (name, header); all at the predicted pose but the last.
DECOMPOSITION = (
    ("predicted", "predicted (chosen mesh, FFD)"),
    ("chosen_no_ffd", "chosen mesh, no FFD"),
    ("sedan", "sedan, FFD"),
    ("true_template", "true template, FFD"),
    ("true_template_no_ffd", "true template, no FFD"),
    ("best_of_8", "best of the 8, FFD"),
    ("truth_pose_true_template", "floor: true pose, true template, no FFD"),
)
#: The full model after the paper's per-image fit at test (``test/refined/<metric>``): an extra row.
REFINED_KEY, REFINED_LABEL = "full+refined", "3D-SDN (full) + test-time fit (Adam 0.03 x 16)"
#: Override keys that do not change what a run computes: left out when comparing a group's runs.
_COSMETIC_KEYS = frozenset({"seed", "ablation", "variant", "experiment", "threads", "summary_file", "run_dir",
                            "trainer.enable_progress_bar", "trainer.enable_model_summary"})
_NO_EXPERIMENT = "none"  # --experiment value of runs recorded without one


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
    for key in ("ablation", "experiment", "variant"):
        if obj.get(key) is not None and not isinstance(obj[key], str):
            raise SummaryError(f"{where}: {key!r} must be a string or null, got {obj[key]!r}")
    if obj.get("seed") is not None and (isinstance(obj["seed"], bool) or not isinstance(obj["seed"], int)):
        raise SummaryError(f"{where}: 'seed' must be an integer or null, got {obj['seed']!r}")
    if not isinstance(obj.get("overrides", []), list):
        raise SummaryError(f"{where}: 'overrides' must be a list, got {obj['overrides']!r}")
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


# --------------------------------------------------------------------------- grouping
def _override_key(override: str) -> str:
    return override.split("=", 1)[0].lstrip("+~")


def settings_of(record: Mapping[str, Any]) -> tuple[str, ...]:
    """The record's command-line overrides that change what it computes (all but the seed, the ablation, the
    experiment and :data:`_COSMETIC_KEYS`), sorted."""
    overrides = [str(o) for o in record.get("overrides") or []]
    return tuple(sorted(o for o in overrides
                        if _override_key(o) not in _COSMETIC_KEYS and not _override_key(o).startswith("hydra.")))


def row_key(record: Mapping[str, Any]) -> str:
    """The row a run belongs to: its ablation (None -> ``full``), ``<ablation>:<variant>`` for a named variant."""
    ablation = record.get("ablation") or "full"
    return f"{ablation}:{record['variant']}" if record.get("variant") else ablation


def group_runs(records: Iterable[Mapping[str, Any]]) -> dict[str | None, dict[str, list[dict[str, Any]]]]:
    """Geometric runs by experiment, then row (:func:`row_key`): one run per (seed, settings), the latest
    successful one (a failed run only where none succeeded), in input order."""
    latest: dict[tuple, tuple[tuple[bool, datetime, int], dict[str, Any]]] = {}
    for order, record in enumerate(records):
        if record.get("branch") != "geometric":
            continue
        identity = (record.get("experiment"), row_key(record), record.get("seed"), settings_of(record))
        rank = (record.get("status") == "ok", _finished(record), order)
        if identity not in latest or rank > latest[identity][0]:
            latest[identity] = (rank, dict(record))
    groups: dict[str | None, dict[str, list[dict[str, Any]]]] = {}
    for (experiment, ablation, _, _), (_, record) in sorted(latest.items(), key=lambda item: item[1][0][2]):
        groups.setdefault(experiment, {}).setdefault(ablation, []).append(record)
    return groups


def choose_experiment(groups: Mapping[str | None, Mapping[str, list[Mapping[str, Any]]]],
                      wanted: str | None) -> str | None:
    """``wanted`` (``'none'``: runs without an experiment), else the experiment of the latest successful run."""
    if wanted is not None:
        key = None if wanted == _NO_EXPERIMENT else wanted
        if key not in groups:
            known = sorted(_NO_EXPERIMENT if k is None else k for k in groups)
            raise InputError(f"--experiment {wanted!r}: no geometric run of that experiment in the inputs "
                             f"(found: {', '.join(known) or 'none'})")
        return key
    stamps = [(r.get("status") == "ok", _finished(r), experiment)
              for experiment, ablations in groups.items() for runs in ablations.values() for r in runs]
    return max(stamps, key=lambda s: (s[0], s[1]))[2] if stamps else None


# --------------------------------------------------------------------------- table
def _number(value: Any) -> float | None:
    if value is None or isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def summarize(values: Sequence[float]) -> dict[str, Any] | None:
    """``mean``, sample ``std`` (None for one value), ``n`` and the ``values``; None without values."""
    if not values:
        return None
    return {"mean": statistics.fmean(values), "std": statistics.stdev(values) if len(values) > 1 else None,
            "n": len(values), "values": list(values)}


def _run_config(record: Mapping[str, Any]) -> dict[str, Any]:
    """Frame ``image_size`` ``[W, H]`` and ``crop_size`` from the run's saved ``config.yaml`` (empty if absent)."""
    from omegaconf import OmegaConf
    from omegaconf.errors import OmegaConfBaseException

    path = Path(str(record.get("run_dir") or "")) / "config.yaml"
    if not record.get("run_dir") or not path.is_file():
        return {}
    try:
        cfg = OmegaConf.to_container(OmegaConf.load(path), resolve=False)
    except (OSError, OmegaConfBaseException) as exc:
        raise SummaryError(f"{path}: not a readable run config: {exc}") from exc
    found = {"image_size": (cfg.get("data") or {}).get("image_size"),
             "crop_size": (cfg.get("datamodule") or {}).get("crop_size")}
    return {k: v for k, v in found.items() if v is not None}


def _source(record: Mapping[str, Any]) -> dict[str, Any]:
    return {k: record.get(k) for k in ("run_dir", "finished", "seed", "status", "_source", "tested_checkpoint",
                                       "selected_by")}


def _tested(source: Mapping[str, Any]) -> str:
    """Which weights a run's test figures come from (its summary's ``tested_checkpoint``, ``selected_by``)."""
    tested = source.get("tested_checkpoint")
    if tested == "best":
        return f"the checkpoint selected by {source.get('selected_by') or 'validation'}"
    if tested == "final":
        return "the weights at the end of fitting (no checkpoint selected)"
    return "tested weights not recorded (a run from before 2026-11-24: selected on the test part)"


def _row(key: str, label: str, runs: Sequence[Mapping[str, Any]], columns: Sequence[Column]) -> dict[str, Any]:
    ok = [r for r in runs if r.get("status") == "ok"]
    row: dict[str, Any] = {
        "key": key, "label": label, "status": "ok" if ok else ("failed" if runs else "not run"),
        "n": len(ok), "failed": len(runs) - len(ok), "seeds": [r.get("seed") for r in ok],
        "metrics": {c.key: summarize([v for r in ok if (v := _number(r["metrics"].get(c.key))) is not None])
                    for c in columns},
        "paper": {c.key: PAPER.get(key, {}).get(c.key) for c in columns},
        "sources": [_source(r) for r in runs],
    }
    settings = sorted({settings_of(r) for r in ok})
    if len(settings) > 1:
        row["warning"] = (f"its {len(ok)} runs differ in more than the seed: "
                          + "; ".join(" ".join(s) or "(no overrides)" for s in settings))
    return row


def _sizes(rows: Sequence[Mapping[str, Any]], configs: Mapping[str, Mapping[str, Any]]) -> dict[str, list]:
    """The distinct frame and crop sizes of the table's successful runs (from their config.yaml)."""
    found: dict[str, list] = {"image_size": [], "crop_size": []}
    for row in rows:
        for source in row["sources"]:
            config = configs.get(str(source.get("run_dir")), {}) if source.get("status") == "ok" else {}
            for name in found:
                if name in config and config[name] not in found[name]:
                    found[name].append(config[name])
    return found


def _refined_record(record: Mapping[str, Any]) -> dict[str, Any]:
    """A full-model run's figures after the test-time fit, under the plain ``test/`` names."""
    metrics = {"test/" + k.removeprefix("test/refined/"): v for k, v in record["metrics"].items()
               if k.startswith("test/refined/")}
    return {**record, "metrics": metrics}


def _interval(values: Sequence[float]) -> dict[str, Any]:
    """Mean and two-sided 95 % Student-t interval of ``values`` (no interval for one value)."""
    mean = statistics.fmean(values)
    if len(values) < 2:
        return {"mean": mean, "low": None, "high": None, "n": len(values), "values": list(values)}
    from scipy.stats import t

    half = float(t.ppf(0.975, len(values) - 1)) * statistics.stdev(values) / math.sqrt(len(values))
    return {"mean": mean, "low": mean - half, "high": mean + half, "n": len(values), "values": list(values)}


def _by_seed(runs: Sequence[Mapping[str, Any]], key: str) -> dict[Any, float]:
    return {r.get("seed"): v for r in runs if r.get("status") == "ok"
            and (v := _number(r["metrics"].get(key))) is not None}


def paired_differences(rows: Sequence[Mapping[str, Any]], runs: Mapping[str, Sequence[Mapping[str, Any]]]
                       ) -> list[dict[str, Any]]:
    """Each row against the full model over the seeds both ran (runs of one seed share the data, the network's
    initialisation and, until the joint stage, the training itself): per attribute column the paired
    difference ``row - full`` with its 95 % interval, and for the reprojection error how much lower the full
    model's is, relative to the row's (``full_lower``, over the same seeds)."""
    full = runs.get("full", [])
    out = []
    for row in rows:
        if row["key"] == "full" or row["status"] != "ok":
            continue
        mine = runs.get(row["key"], [])
        entry: dict[str, Any] = {"key": row["key"], "label": row["label"], "differences": {}}
        for column in ATTRIBUTE_COLUMNS:
            theirs, ours = _by_seed(mine, column.key), _by_seed(full, column.key)
            seeds = sorted(set(theirs) & set(ours), key=str)
            if not seeds:
                continue
            diff = _interval([theirs[s] - ours[s] for s in seeds])
            diff["seeds"] = seeds
            if column.key == "test/reprojection_error_image":
                base = statistics.fmean(theirs[s] for s in seeds)
                diff["full_lower"] = {k: (v / base if v is not None and base else None)
                                      for k, v in (("mean", diff["mean"]), ("low", diff["low"]),
                                                   ("high", diff["high"]))}
            entry["differences"][column.key] = diff
        if entry["differences"]:
            out.append(entry)
    return out


def decomposition(rows: Sequence[Mapping[str, Any]], runs: Mapping[str, Sequence[Mapping[str, Any]]]
                  ) -> list[dict[str, Any]]:
    """Per row with ``test/decomposition/...`` figures: their means over seeds and the shares of the error
    (``floor``; ``pose``: true template without FFD at the predicted pose minus the floor; ``mesh_choice``:
    predicted minus the true template, both with the FFD; ``ffd``: predicted minus the chosen mesh without FFD,
    negative where the FFD helps; ``selection_room``: predicted minus the best of the 8)."""
    out = []
    for row in rows:
        mine = [r for r in runs.get(row["key"], []) if r.get("status") == "ok"]
        means = {}
        for name, _ in DECOMPOSITION:
            values = [v for r in mine if (v := _number(r["metrics"].get(f"test/decomposition/{name}"))) is not None]
            if values:
                means[name] = summarize(values)
        if len(means) != len(DECOMPOSITION):
            continue
        m = {k: v["mean"] for k, v in means.items()}
        shares = {"floor": m["truth_pose_true_template"],
                  "pose": m["true_template_no_ffd"] - m["truth_pose_true_template"],
                  "mesh_choice": m["predicted"] - m["true_template"],
                  "ffd": m["predicted"] - m["chosen_no_ffd"],
                  "selection_room": m["predicted"] - m["best_of_8"]}
        out.append({"key": row["key"], "label": row["label"], "n": len(mine), "values": means, "shares": shares})
    return out


def fit_gap(rows: Sequence[Mapping[str, Any]], runs: Mapping[str, Sequence[Mapping[str, Any]]]
            ) -> list[dict[str, Any]]:
    """Per row, how far training over-fits: ``train/loss_pred`` (the last epoch's mean over the training part),
    ``test/loss_pred`` (the tested weights, on the test part) and their ratio test / train per run, each
    :func:`summarize`-d over the row's successful runs that logged both."""
    out = []
    for row in rows:
        pairs = [(train, test) for r in runs.get(row["key"], []) if r.get("status") == "ok"
                 and (train := _number(r["metrics"].get("train/loss_pred"))) is not None
                 and (test := _number(r["metrics"].get("test/loss_pred"))) is not None and train > 0]
        if pairs:
            out.append({"key": row["key"], "label": row["label"], "n": len(pairs),
                        "train": summarize([a for a, _ in pairs]), "test": summarize([b for _, b in pairs]),
                        "ratio": summarize([b / a for a, b in pairs])})
    return out


def build_table(groups: Mapping[str | None, Mapping[str, list[Mapping[str, Any]]]], experiment: str | None,
                configs: Mapping[str, Mapping[str, Any]] | None = None) -> dict[str, Any]:
    """The table of ``experiment``'s runs as a JSON-ready dict.

    Args:
        groups: :func:`group_runs` output.
        experiment: the experiment whose runs fill the table (:func:`choose_experiment`).
        configs: run directory -> :func:`_run_config` (frame and crop sizes for the headers).
    """
    runs = dict(groups.get(experiment, {}))
    columns = (*ATTRIBUTE_COLUMNS, *MESH_COLUMNS)
    rows = []
    for key, label in ROWS:
        rows.append(_row(key, label, runs.get(key, []), columns))
        for variant in sorted(k for k in runs if k.split(":", 1)[0] == key and ":" in k):
            rows.append(_row(variant, f"{label}, {variant.split(':', 1)[1]}", runs[variant], columns))
        if key == "full":
            refined = [_refined_record(r) for r in runs.get("full", []) if r.get("status") == "ok"]
            if any(r["metrics"] for r in refined):  # a row of its own, paired with full like any other
                runs[REFINED_KEY] = refined
                rows.append(_row(REFINED_KEY, REFINED_LABEL, refined, columns))
    rows += [_row(key, label, runs[key], columns) for key, label in EXTRA_ROWS if runs.get(key)]
    sizes = _sizes(rows, configs or {})
    warnings = [f"{row['label']}: {row['warning']}" for row in rows if "warning" in row]
    for name, values in sizes.items():
        if len(values) > 1:
            warnings.append(f"the runs' {name} differ: {values}")
    frame = "x".join(str(v) for v in sizes["image_size"][0]) if len(sizes["image_size"]) == 1 else "W x H"
    crop = f"{sizes['crop_size'][0]}-px crops" if len(sizes["crop_size"]) == 1 else "crop pixels"

    def header(column: Column) -> dict[str, Any]:
        return {"key": column.key, "header": column.header.format(frame=frame, crop=crop),
                "higher_is_better": column.higher_is_better, "scale": column.scale, "decimals": column.decimals,
                "paper_header": column.short}

    known = {r["key"] for r in rows}
    return {
        "table": "3D-SDN Table 2: 3D attribute prediction (geometric branch)",
        "experiment": _NO_EXPERIMENT if experiment is None else experiment,
        "frame_size": sizes["image_size"][0] if len(sizes["image_size"]) == 1 else None,
        "crop_size": sizes["crop_size"][0] if len(sizes["crop_size"]) == 1 else None,
        "columns": [header(c) for c in ATTRIBUTE_COLUMNS],
        "mesh_columns": [header(c) for c in MESH_COLUMNS],
        "rows": rows,
        "paired": paired_differences(rows, runs),
        "decomposition": decomposition(rows, runs),
        "fit_gap": fit_gap([r for r in rows if r["key"] != REFINED_KEY], runs),
        "ignored_ablations": sorted(set(runs) - known),
        "other_experiments": sorted(_NO_EXPERIMENT if k is None else k for k in groups if k != experiment),
        "warnings": warnings,
    }


# --------------------------------------------------------------------------- markdown
def _format(value: float | None, column: Mapping[str, Any]) -> str:
    return "n/a" if value is None else f"{value * column['scale']:.{column['decimals']}f}"


def _cell(summary: Mapping[str, Any] | None, column: Mapping[str, Any], runs: int) -> str:
    """``mean ± std`` in the column's units; ``(n=k)`` when fewer runs than the row's had the metric."""
    if summary is None:
        return "n/a"
    text = _format(summary["mean"], column)
    if summary["std"] is not None:
        text += f" ± {_format(summary['std'], column)}"
    return text + (f" (n={summary['n']})" if summary["n"] != runs else "")


def _arrow(column: Mapping[str, Any]) -> str:
    return {True: " ↑", False: " ↓", None: ""}[column["higher_is_better"]]


def _markdown_table(rows: Sequence[Mapping[str, Any]], columns: Sequence[Mapping[str, Any]],
                    paper: bool) -> list[str]:
    paper_columns = [c for c in columns if paper and any(r["paper"].get(c["key"]) is not None for r in rows)]
    header = ["Method", "n", *(c["header"] + _arrow(c) for c in columns),
              *(f"paper: {c['paper_header']}" for c in paper_columns)]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in rows:
        if row["status"] == "ok":
            cells = [_cell(row["metrics"][c["key"]], c, row["n"]) for c in columns]
        else:
            cells = [row["status"]] * len(columns)
        refs = [_format(row["paper"][c["key"]], c) if row["paper"][c["key"]] is not None else "" for c in paper_columns]
        lines.append("| " + " | ".join([row["label"], str(row["n"]), *cells, *refs]) + " |")
    return lines


def _difference(diff: Mapping[str, Any] | None, column: Mapping[str, Any]) -> str:
    """``+d [low, high]`` in the column's units (no interval from one pair)."""
    if diff is None:
        return ""
    scale, decimals = column["scale"], column["decimals"] + 1

    def f(v: float) -> str:
        return f"{v * scale:+.{decimals}f}"
    text = f(diff["mean"])
    return text + (f" [{f(diff['low'])}, {f(diff['high'])}]" if diff["low"] is not None else " (1 pair)")


def _paired_markdown(table: Mapping[str, Any]) -> list[str]:
    if not table.get("paired"):
        return []
    columns = table["columns"][:4]
    header = ["Row", "seeds", *(f"Δ {c['header']}" for c in columns), "3D-SDN (full): reprojection error lower by"]
    lines = ["", "## Paired with 3D-SDN (full)", "",
             "Each row minus 3D-SDN (full), seed by seed (runs of one seed share the data, the initialisation and, "
             "until the joint stage, the training), in the columns' units: mean difference and its 95 % Student-t "
             "interval over the pairs. The last column is the reprojection error's paired difference relative to "
             "the row's own mean (the paper's 3D-SDN is 65 % lower than its w/o L_reproj).", "",
             "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for entry in table["paired"]:
        diffs = entry["differences"]
        seeds = next(iter(diffs.values()))["seeds"]
        lower = diffs.get("test/reprojection_error_image", {}).get("full_lower")
        cut = ""
        if lower is not None and lower["mean"] is not None:
            cut = f"{lower['mean'] * 100:.0f} %"
            if lower["low"] is not None:
                cut += f" [{lower['low'] * 100:.0f}, {lower['high'] * 100:.0f}]"
        cells = [_difference(diffs.get(c["key"]), c) for c in columns]
        lines.append("| " + " | ".join([entry["label"], ",".join(map(str, seeds)), *cells, cut]) + " |")
    return lines


def _decomposition_markdown(table: Mapping[str, Any]) -> list[str]:
    if not table.get("decomposition"):
        return []
    headers = [h for _, h in DECOMPOSITION]
    lines = ["", "## Where the reprojection error comes from", "",
             "The test objects with a known (approximating) template, scored at the predicted pose with other meshes "
             "and FFDs, and at the true pose (x1e-3, per pixel of the frame; mean over seeds). The true template is "
             "the bank's nearest to the car that drew the object; with held-out vehicles no bank mesh is exact, so "
             "the floor is not zero.", "",
             "| Row | n | " + " | ".join(headers) + " |", "|" + "---|" * (len(headers) + 2)]
    for entry in table["decomposition"]:
        cells = [f"{entry['values'][name]['mean'] * 1e3:.2f}" for name, _ in DECOMPOSITION]
        lines.append("| " + " | ".join([entry["label"], str(entry["n"]), *cells]) + " |")
    lines += ["", "| Row | floor | pose (true template, no FFD, minus floor) | mesh choice (predicted minus true "
              "template) | FFD (predicted minus chosen without FFD) | selection room (predicted minus best of 8) |",
              "|---|---|---|---|---|---|"]
    for entry in table["decomposition"]:
        sh = entry["shares"]
        total = entry["values"]["predicted"]["mean"]

        def part(v: float, total: float = total) -> str:
            return f"{v * 1e3:+.2f} ({v / total * 100:+.0f} %)" if total else f"{v * 1e3:+.2f}"
        lines.append(f"| {entry['label']} | {sh['floor'] * 1e3:.2f} ({sh['floor'] / total * 100:.0f} %) | "
                     f"{part(sh['pose'])} | {part(sh['mesh_choice'])} | {part(sh['ffd'])} | "
                     f"{part(sh['selection_room'])} |" if total else f"| {entry['label']} | n/a | | | | |")
    return lines


def _fit_gap_markdown(table: Mapping[str, Any]) -> list[str]:
    if not table.get("fit_gap"):
        return []
    lines = ["", "## Over-fitting: L_pred on the training and the test part", "",
             "L_pred (the paper's attribute loss) averaged over the training part in the last epoch, and over the "
             "test part with the tested weights; the ratio test / train per run (1: no over-fitting). Mean ± sample "
             "std over the row's runs.", "",
             "| Row | n | train L_pred (last epoch) | test L_pred | test / train |", "|---|---|---|---|---|"]
    loss, ratio = {"scale": 1.0, "decimals": 4}, {"scale": 1.0, "decimals": 2}
    for entry in table["fit_gap"]:
        n = entry["n"]
        lines.append(f"| {entry['label']} | {n} | {_cell(entry['train'], loss, n)} | {_cell(entry['test'], loss, n)} | "
                     f"{_cell(entry['ratio'], ratio, n)} |")
    return lines


def render_markdown(table: Mapping[str, Any]) -> str:
    """Markdown of :func:`build_table`'s dict: Table 2 with the paper's rows beside it, then the mesh choice."""
    frame = table["frame_size"]
    lines = [f"# {table['table']}", "",
             f"Experiment `{table['experiment']}`; frame {'x'.join(map(str, frame)) if frame else 'size unknown'} "
             "(W x H, the working size: the reprojection error's denominator; the paper's is 624x192). "
             "Each cell: mean ± sample std over the row's n runs (seeds).", ""]
    lines += _markdown_table(table["rows"], table["columns"], paper=True)
    lines += ["", "Higher is better for orientation similarity, lower for the errors. Distance error: "
              "|log t - log t~|, t the distance to the box centre. Reprojection error: per object, the image "
              "pixels of its crop window (the visible 2D box grown by the crop margin) where the hard silhouette "
              "of the predicted mesh and the visible mask disagree (closer objects and pixels outside the image "
              "left out), over the frame's W x H pixels; mean over objects. The soft crop mean is the training "
              "loss L_reproj over the crop (not comparable with the paper).",
              "", "## Mesh selection", ""]
    lines += _markdown_table([r for r in table["rows"] if r["key"] != REFINED_KEY], table["mesh_columns"],
                             paper=False)  # the test-time fit keeps the mesh choice
    lines += ["", "Mesh accuracy: objects whose true template is known. Floors: always the most frequent template "
              "of the training part; a uniform guess. Ceiling: objects whose true template has the lowest soft "
              "L_reproj at the true pose without FFD. Selection regret: soft L_reproj (crop) of the chosen "
              "template minus the lowest over the 8, both at the predicted pose and FFD."]
    lines += _paired_markdown(table)
    lines += _decomposition_markdown(table)
    lines += _fit_gap_markdown(table)
    notes = [f"- {row['label']}: {row['failed']} failed run(s) left out" for row in table["rows"] if row["failed"]]
    notes += [f"- warning: {w}" for w in table["warnings"]]
    if table["ignored_ablations"]:
        notes.append(f"- runs of other ablations not in the table: {', '.join(table['ignored_ablations'])}")
    if table["other_experiments"]:
        notes.append(f"- runs of other experiments (--experiment): {', '.join(table['other_experiments'])}")
    sources = [f"- {row['label']}: {s.get('run_dir') or s.get('_source')} (seed {s.get('seed')}, {s.get('status')}, "
               f"finished {s.get('finished') or '?'}; test figures from {_tested(s)})"
               for row in table["rows"] for s in row["sources"]]
    if notes:
        lines += ["", "Notes:", *notes]
    if sources:
        lines += ["", "Sources:", *sources]
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------- CLI
def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="sdn3d-table2", description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--summary", action="append", default=[], metavar="JSONL",
                        help="summary.jsonl written by sdn3d-train (repeatable)")
    parser.add_argument("--multirun", action="append", default=[], metavar="DIR",
                        help="run or multirun directory searched for summary.json files (repeatable)")
    parser.add_argument("--experiment", default=None,
                        help="the experiment whose runs fill the table ('none': runs without one; default: the "
                             "experiment of the latest successful run)")
    parser.add_argument("--out", default="outputs/tables", help="output directory (default: %(default)s)")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    return run_argparse_cli("table2", _parser(), _main, argv)


def _main(args: argparse.Namespace) -> int:
    if not args.summary and not args.multirun:
        raise InputError("give at least one --summary FILE or --multirun DIR")
    groups = group_runs(load_runs(args.summary, args.multirun))
    experiment = choose_experiment(groups, args.experiment)
    configs = {str(r.get("run_dir")): _run_config(r)
               for runs in groups.get(experiment, {}).values() for r in runs if r.get("status") == "ok"}
    table = build_table(groups, experiment, configs)
    for warning in table["warnings"]:
        print(f"sdn3d-table2: warning: {warning}", file=sys.stderr)
    out = Path(args.out)
    write_json_atomic(out / "table2.json", table)
    write_text_atomic(out / "table2.md", render_markdown(table))
    print(render_markdown(table), end="")
    print(f"wrote {out / 'table2.md'} and {out / 'table2.json'}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
