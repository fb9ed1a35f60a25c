"""``sdn3d-bench``: the editing benchmark (paper Table 1), see :mod:`sdn3d.evaluation.edit_benchmark`.

Configuration ``conf/bench.yaml`` (Hydra overrides as arguments). One run evaluates every source scene of
``proposals`` (default ``[semantic, gt]``): first 3D-SDN as a user runs it, on the semantic branch's predicted
masks and semantics, then the *oracle* row on the frame's ground-truth masks and semantics, each labelled in
every output. ``scene=oracle`` (ground-truth geometry too) is one pass. Outputs, written all at once:

    results.json     settings, which source scenes (``info.sources`` / ``info.source_labels``) and which generator
                     drew each method (``info.generators``: checkpoint, whether it takes pose / normal maps); per
                     source scene: summary (means per compose mode / method / region / metric, latency) and
                     every entry
    table1.md        the paper's Table 1 layout (LPIPS whole / all / largest) plus L1, SSIM, PSNR, one row per
                     source scene, method and compose mode: ``full`` = the generator's whole picture (the paper's
                     protocol), ``edited`` = the source outside the method's edit region (what ``sdn3d-edit``
                     gives a user); each row names its generator
    index.html       example grids (source | target | 3D-SDN | 2D | 2D+, one row per source scene and compose
                     mode) with metrics
    examples/*.png   the grids

A generated benchmark (its dataset's ``synth_manifest.json`` beside it) is counted against what the dataset asked
for: a kind with fewer entries to score (a sequence whose test frames have no partly hidden car gets no
occluder-removed entry) is warned about once on stderr when the entries are scored, naming the sequences and why
(:mod:`sdn3d.data.synth.entry_report`), and recorded (``info.benchmark_short``, ``table1.md``).

An earlier output directory is replaced (``overwrite=true``) only when it holds nothing but the files its
``results.json`` lists (``outputs``) and none of this run's inputs (the benchmark file, the dataset, a checkpoint):
else the run stops with exit 2 naming the file, and nothing is deleted (:func:`output_rules`, as ``sdn3d-edit``).

``run=<dir>`` takes the branches' checkpoints from the ``sdn3d-train`` summaries under ``dir`` (a demo output such
as ``outputs/demo``, one run directory, or a training root), as ``sdn3d-edit run=`` does
(:func:`sdn3d.runs.checkpoints_from_run`): per branch the latest run with status ok, its best checkpoint else its
last. ``checkpoints.<branch>=`` given explicitly wins; ``checkpoints.textural_2d`` is only ever given. Each
branch's file is printed on stderr; ``results.json`` records them all (``info.checkpoints``: the file, and for a
run's choice its ``summary.json``, which checkpoint and when the run finished).

The 2D and 2D+ rows are drawn by 3D-SDN's generator (whose inputs include pose and normal maps from the
de-rendered geometry) unless ``checkpoints.textural_2d`` gives a generator trained without them
(``sdn3d-train branch=textural model.use_pose=false model.use_normal=false``): the paper's baselines without 3D
knowledge.

Exit status: 0 done; 2 bad input (missing benchmark / checkpoint, a ``run`` that is not a training output directory
or lacks a branch the benchmark needs, no semantic checkpoint for the predicted row,
no matching frames, no entry to evaluate or every entry's points outside ``frame_size`` unless ``allow_empty=true``;
nothing written).; 1 every entry failed (the results are written; each entry's error is in results.json).
"""

from __future__ import annotations

import html
import math
import re
import sys
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import torch
from rich.console import Console

from sdn3d.cli._config import compose_config, print_help_if_asked
from sdn3d.cli._errors import run_cli
from sdn3d.editing.appearance import PictureMode
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.errors import InputError
from sdn3d.evaluation.edit_benchmark import METHODS, PROPOSALS, REGIONS, SCENES, SOURCE_LABELS, Scene
from sdn3d.geometric.fit import FitSettings
from sdn3d.io import check_output_dir, staged_directory
from sdn3d.proposals import Proposals
from sdn3d.runs import checkpoints_from_run, given_checkpoints

__all__ = ["main", "run_bench", "all_failed", "table1_markdown", "examples_html", "generator_info", "bench_modes",
           "bench_passes", "bench_checkpoints", "check_entries", "run_counterfactual_bench"]

MARKER = "results.json"
#: What sdn3d-bench wrote before its results.json listed its ``outputs``: an earlier result of it holding these only
#: is replaced.
LEGACY_OUTPUTS = re.compile(r"results\.json|table1\.md|index\.html|examples/\d{4}\.png")
LABELS = {"2d": "2D", "2d+": "2D+", "3d-sdn": "3D-SDN (ours)"}
ROW_ORDER = ("2d", "2d+", "3d-sdn")  # the paper's row order
COMPOSE_LABELS = {"photo": "photo (own pixels through 3D; what sdn3d-edit gives)",
                  "full": "generator, full (paper protocol)", "edited": "generator, edited"}
#: Short mode names for grid titles.
MODE_SHORT = {"photo": "photo", "full": "generator full", "edited": "generator edited"}
KIND_TITLES = {"move": "Move", "rotate": "Move with a turn of 15 degrees or more", "zoom": "Zoom (distance changed)",
               "delete": "Delete",
               "occluder_removed": "Occluder removed (not in the paper's benchmark): a car in front of a partly hidden "
                                   "one is deleted, the target shows it whole"}
#: The table's short name of each source scene (:data:`SOURCE_LABELS` has the long ones).
SOURCE_SHORT = {"semantic": "predicted", "gt": "oracle: GT masks + semantics",
                "oracle": "oracle: GT masks, semantics + geometry"}
console = Console(stderr=True)


def _fmt(stat: dict | None, digits: int = 4) -> str:
    if not stat or stat.get("n", 0) == 0 or not math.isfinite(stat["mean"]):
        return "n/a"
    return f"{stat['mean']:.{digits}f}"


def generator_info(path: str | Path, spec: Any, tag: str) -> dict:
    """What results.json and table1.md say about a textural generator: ``tag`` (the table's short name), its
    checkpoint and which of its inputs it takes (``spec``: :class:`~sdn3d.nets.pix2pixhd.TexturalSpec`)."""
    maps = [name for name, used in (("pose", spec.use_pose), ("normal", spec.use_normal)) if used]
    takes = " + ".join(maps) + " maps" if maps else "no pose or normal maps"
    return {"tag": tag, "checkpoint": str(path), "use_pose": bool(spec.use_pose), "use_normal": bool(spec.use_normal),
            "use_codes": bool(spec.use_codes), "description": f"{tag} ({takes})"}


def _rows(summaries: dict, info: dict) -> list[tuple[str, str, str, dict]]:
    """``(source, method, compose, {region: {metric: stat}})`` per table row: every source scene (predicted
    first), every compose mode, the paper's row order."""
    return [(s, m, c, summaries[s]["methods"].get(c, {}).get(m, {}))
            for s in info["sources"] for c in info["compose"] for m in ROW_ORDER]


def _generators_note(info: dict) -> list[str]:
    gens = info["generators"]
    lines = [f"- {g['tag']}: `{g['checkpoint']}` (inputs: semantics, boundaries"
             + (", texture codes" if g["use_codes"] else "") + (", pose map" if g["use_pose"] else "")
             + (", normal map" if g["use_normal"] else "") + f"): draws {', '.join(LABELS[m] for m in ms)}"
             for g, ms in _generator_methods(gens)]
    if gens["2d"]["checkpoint"] == gens["3d-sdn"]["checkpoint"]:
        lines.append("- The 2D and 2D+ rows use the 3D-informed generator: its pose and normal maps come from "
                     "3D-SDN's de-rendered geometry (moved with each region), so these baselines are not free of 3D "
                     "knowledge. `checkpoints.textural_2d=` a generator trained with `model.use_pose=false "
                     "model.use_normal=false` draws them without (the paper's baselines).")
    return lines


def _generator_methods(gens: dict) -> list[tuple[dict, list[str]]]:
    """``[(generator, [methods it draws])]`` in first-use order of :data:`ROW_ORDER`."""
    out: dict[str, tuple[dict, list[str]]] = {}
    for m in ROW_ORDER:
        out.setdefault(gens[m]["tag"], (gens[m], []))[1].append(m)
    return list(out.values())


def _header(summaries: dict, info: dict) -> list[str]:
    first = summaries[info["sources"][0]]
    sources = "; ".join(f"*{SOURCE_SHORT[s]}* = {SOURCE_LABELS[s]}" for s in info["sources"])
    oracle_only = [] if any(not info["source_oracle"][s] for s in info["sources"]) else [
        "", "**Oracle rows only**: no row here runs on the semantic branch's predictions (`proposals=[semantic, gt]` "
            "with `checkpoints.semantic=` gives the predicted row a user gets)."]
    return ["# Editing benchmark (3D-SDN Table 1 layout)", "",
            f"{first['evaluated']} of {first['entries']} entries evaluated on `{info['benchmark']}` "
            f"({info['data']}), working size {info['image_size'][0]}x{info['image_size'][1]}. "
            f"Source scenes: {sources}. " + ("The proposals' vehicles are fitted to their masks at test time "
                                             "(`fit_proposals=true`, as `sdn3d-edit` does). "
                                             if info.get("fit_proposals") else "") +
            ("A modify moves its object so that the point `from` lands on `to` (`modify_anchor=pick`, as the 2D "
             "baselines paste it). " if info.get("modify_anchor") == "pick" else
             "A modify puts the de-rendered box centre at `to` (`modify_anchor=centre`). "
             if info.get("modify_anchor") else "") +
            "Lower LPIPS / L1 and higher SSIM / PSNR are better; *all* = the union of the edited objects' source and "
            "target regions, *largest* = the largest edited object's target box (crop), *objects* = the target's "
            "visible pixels of the edited objects (the cars themselves, apart from the road filled behind them).",
            *oracle_only, "",
            "Mode *photo* = the photo appearance (each edited car drawn with the source frame's own pixels through "
            "its 3D shape, vacated road inpainted; 2D / 2D+ paste the car's own pixels moved in 2D over the same "
            "fill): what `sdn3d-edit` gives a user. *generator, full* = the generator's whole picture (the paper's "
            "protocol); *generator, edited* = the source frame with only the method's edit region (dilated "
            f"{info['dilate_px']} px, feathered {info['feather_px']} px) redrawn by the generator.", "",
            "Generators:", *_generators_note(info), ""]


def table1_markdown(summaries: dict, info: dict, comparisons: dict | None = None) -> str:
    """The paper's Table 1 layout (rows 2D, 2D+, 3D-SDN per source scene and compose mode) from
    ``{source: summarize(...)}`` (:func:`sdn3d.evaluation.edit_benchmark.summarize`) and results.json's info;
    ``comparisons`` (:func:`paired_comparisons`) adds who won to the headline."""
    from sdn3d.data.synth.entry_report import KindCount, shortfall_sentences

    rows = _rows(summaries, info)
    gens = info["generators"]
    has_lpips = any("lpips" in stats.get("whole", {}) for *_, stats in rows)
    head = "| Scene | Method | Generator | Compose |"

    def lead(s: str, m: str, c: str) -> str:
        generator = gens[m]["tag"] if c != PictureMode.PHOTO else "none"
        return f"| {SOURCE_SHORT[s]} | {LABELS[m]} | {generator} | {COMPOSE_LABELS[c]} |"

    lines = _headline(summaries, info, comparisons) + _header(summaries, info) + ["## All rows", ""]
    if has_lpips:
        lines += [f"{head} " + " | ".join(f"LPIPS ({r})" for r in REGIONS) + " |", "|---" * (4 + len(REGIONS)) + "|"]
        lines += [lead(s, m, c) + " " + " | ".join(_fmt(st.get(r, {}).get("lpips")) for r in REGIONS) + " |"
                  for s, m, c, st in rows]
        lines.append("")
    else:
        lines += ["LPIPS is left out: no LPIPS weights were given (`lpips_weights=`, see sdn3d.nets.lpips).", ""]
    lines += [f"{head} " + " | ".join(f"{k} ({r})" for k in ("L1", "SSIM", "PSNR") for r in REGIONS) + " |",
              "|---" * (4 + 3 * len(REGIONS)) + "|"]
    lines += [lead(s, m, c) + " " + " | ".join(_fmt(st.get(r, {}).get(k), 2 if k == "psnr" else 4)
                                             for k in ("l1", "ssim", "psnr") for r in REGIONS) + " |"
              for s, m, c, st in rows]
    lines += ["", "Layout diagnostic (not in the paper; needs no trained generator): mean IoU between where each "
                  "method draws the edited objects and where the target frame shows them.", "",
              "| Scene | Method | edited-object mask IoU |", "|---|---|---|"]
    lines += [f"| {SOURCE_SHORT[s]} | {LABELS[m]} | {_fmt(st.get('layout', {}).get('mask_iou'), 3)} |"
              for s, m, c, st in rows if c == info["compose"][0]]
    lines += _by_kind_lines(summaries, info)
    short = {k: KindCount.from_json(k, v) for k, v in (info.get("benchmark_short") or {}).items()}
    lines += [f"\n**Fewer entries than asked for.** {sentence}." for sentence in shortfall_sentences(short)]
    lines.append("")
    for s in info["sources"]:
        lat, failed = summaries[s]["latency_ms"], summaries[s]["failed"]
        modes = info["compose"]
        compose = f"; compose edited adds {_fmt(lat['compose'], 1)} ms" if PictureMode.EDITED in modes else ""
        compose += f"; the photo appearance takes {_fmt(lat['photo'], 0)} ms" if PictureMode.PHOTO in modes else ""
        lines += [f"*{SOURCE_SHORT[s]}*: 3D-SDN latency per edit (de-render + edit + render, {info['device']}, "
                  f"{info['threads']} threads): mean {_fmt(lat['total'], 0)} ms (de-render {_fmt(lat['derender'], 0)}, "
                  f"edit {_fmt(lat['edit'], 0)}, render {_fmt(lat['render'], 0)} ms{compose}). Entries that failed per "
                  "method: " + ", ".join(f"{LABELS[m]} {failed[m]}" for m in ROW_ORDER) + ".", ""]
    return "\n".join(lines)


_METRIC_NAMES = {"lpips": "LPIPS", "l1": "L1", "ssim": "SSIM", "psnr": "PSNR"}


def headline_columns(summaries: dict, info: dict) -> list[tuple[str, str]]:
    """``[(metric, region)]`` of the headline: LPIPS where it was measured, then L1, SSIM and PSNR, each on *all*,
    *largest* and *objects*."""
    mode = info["compose"][0]
    has_lpips = any("lpips" in summaries[s]["methods"].get(mode, {}).get(m, {}).get("all", {})
                    for s in info["sources"] for m in ROW_ORDER)
    return [(k, r) for k in (["lpips"] if has_lpips else []) + ["l1", "ssim", "psnr"]
            for r in ("all", "largest", "objects")]


def edited_car_groups(records: Sequence[Mapping[str, Any]]) -> dict[int, tuple]:
    """Entry index -> the cars it edits (``results.json`` per-entry records' ``cars``: world and ground-truth
    instance ids), the entry's own index where it names none. Entries that edit the same cars are one group,
    resampled together by the paired bootstrap (:func:`sdn3d.evaluation.paired.paired_difference`): a car is edited
    from several source frames and in both variations of its world (and the generator can draw one occluder pair
    for two slots), and those entries are one piece of evidence, not several."""
    groups: dict[int, tuple] = {}
    for record in records:
        cars = tuple(record.get("cars") or ())
        if cars or record["index"] not in groups:
            groups[record["index"]] = ("cars", *cars) if cars else ("entry", record["index"])
    return groups


def paired_comparisons(entries: dict, summaries: dict, info: dict, ours: str = "3d-sdn", theirs: str = "2d",
                       groups: Mapping[int, Any] | None = None) -> dict:
    """``{source: {"metric/region": PairedDifference.to_dict()}}``: 3D-SDN minus 2D on each headline column, paired
    over the entries both evaluated (``results.json``'s per-entry records), in the headline's mode. ``groups``:
    entry index -> group (:func:`edited_car_groups`); None: every entry its own."""
    from sdn3d.evaluation.paired import compare_entries

    mode, cols = info["compose"][0], headline_columns(summaries, info)
    group_of = None if groups is None else (lambda record: groups[record["index"]])
    return {s: {f"{k}/{r}": d.to_dict() for (k, r), d in compare_entries(entries.get(s, []), mode, ours, theirs,
                                                                         cols, group_of).items()}
            for s in info["sources"]}


def _best(summaries: dict, source: str, mode: str, metric: str, region: str) -> str | None:
    """The method with the best mean on one column (L1 / LPIPS lowest, SSIM / PSNR highest), None without values."""
    from sdn3d.evaluation.paired import LOWER_IS_BETTER

    values = {m: summaries[source]["methods"].get(mode, {}).get(m, {}).get(region, {}).get(metric) for m in ROW_ORDER}
    values = {m: v["mean"] for m, v in values.items() if v and v.get("n", 0) and math.isfinite(v["mean"])}
    if not values:
        return None
    pick = min if metric in LOWER_IS_BETTER else max
    return pick(values, key=values.get)


def _signed(value: float, digits: int) -> str:
    return f"{value:+.{digits}f}"


def who_won_lines(comparisons: dict, summaries: dict, info: dict) -> list[str]:
    """Per source scene, one sentence saying who won (3D-SDN against 2D, the interval of the paired difference
    deciding), then the paired table: the mean difference with its 95 % bootstrap interval and the entries each
    side won."""
    from sdn3d.evaluation.paired import MIN_ENTRIES

    cols = headline_columns(summaries, info)
    lines = ["**Who won.** 3D-SDN against 2D (the stronger of the paper's two baselines in its Table 1), paired over "
             "the same entries: the mean of 3D-SDN minus 2D, its 95 % paired-bootstrap interval, and on how many "
             "entries 3D-SDN was better / worse. Entries that edit the same cars (from other source frames, in either "
             "variation) are resampled together: one car is one piece of evidence. A column counts as won or lost "
             f"only where the interval excludes 0, and only with at least {MIN_ENTRIES} distinct groups of cars.", ""]
    table = ["| Scene | Column | 3D-SDN - 2D [95 % interval] | 3D-SDN better / worse (entries) | verdict |",
             "|---|---|---|---|---|"]
    for s in info["sources"]:
        comp = comparisons.get(s) or {}
        verdicts = [comp.get(f"{k}/{r}", {}).get("verdict", "no entries") for k, r in cols]
        n = max((comp.get(f"{k}/{r}", {}).get("n", 0) for k, r in cols), default=0)
        groups = max((comp.get(f"{k}/{r}", {}).get("groups") or comp.get(f"{k}/{r}", {}).get("n", 0)
                      for k, r in cols), default=0)
        if n == 0:
            lines.append(f"- *{SOURCE_SHORT[s]}*: no entry was evaluated by both methods: no comparison.")
            continue
        won, lost = verdicts.count("better"), verdicts.count("worse")
        unclear = len(cols) - won - lost
        def cols_(k: int) -> str:
            return f"{k} column" + ("" if k == 1 else "s")

        if groups < MIN_ENTRIES:
            ahead = sum(comp.get(f"{k}/{r}", {}).get("mean", 0) * (1 if k not in ("l1", "lpips") else -1) > 0
                        for k, r in cols)
            say = (f"too few entries to call: 3D-SDN's mean is ahead of 2D's in {ahead} of {cols_(len(cols))}, "
                   f"which decides nothing under {MIN_ENTRIES} distinct groups of cars")
        elif won == len(cols):
            say = f"3D-SDN beats 2D in every column ({len(cols)})"
        elif lost == len(cols):
            say = f"3D-SDN loses to 2D in every column ({len(cols)})"
        elif won > lost:
            say = f"3D-SDN is ahead: better in {cols_(won)}, worse in {lost}, no clear difference in {unclear}"
        elif lost > won:
            say = f"2D is ahead: 3D-SDN is worse in {cols_(lost)}, better in {won}, no clear difference in {unclear}"
        else:
            say = f"no winner: 3D-SDN is better in {cols_(won)}, worse in {lost}, no clear difference in {unclear}"
        small = (f" With {n} entries, only a difference whose interval excludes 0 is evidence; a gap in the means "
                 "alone is an anecdote." if n < 30 else "")
        counted = f"{n} entries" + (f", {groups} groups of cars" if groups != n else "")
        lines.append(f"- *{SOURCE_SHORT[s]}* ({counted}): **{say}**.{small}")
        for k, r in cols:
            d = comp.get(f"{k}/{r}")
            if not d or not d.get("n"):
                continue
            digits = 2 if k == "psnr" else 4
            table.append(f"| {SOURCE_SHORT[s]} | {_METRIC_NAMES[k]} ({r}) | {_signed(d['mean'], digits)} "
                         f"[{_signed(d['low'], digits)}, {_signed(d['high'], digits)}] | {d['wins']} / {d['losses']}"
                         f" of {d['n']} | {d['verdict']} |")
    return lines + ["", *table, ""] if len(table) > 2 else lines + [""]


def _headline(summaries: dict, info: dict, comparisons: dict | None = None) -> list[str]:
    """The first screen: Table 1's rows in the first mode (photo, what a user gets), every source scene, only the
    columns that have values, the best value of each column per scene in bold; then who won, with paired
    intervals and win counts (:func:`who_won_lines`) where the per-entry results were given."""
    mode = info["compose"][0]
    cols = headline_columns(summaries, info)
    first = summaries[info["sources"][0]]
    lines = ["# Editing benchmark: headline", "",
             f"{first['evaluated']} entries of `{Path(info['benchmark']).name}`, mode **{COMPOSE_LABELS[mode]}**; "
             "lower L1 / LPIPS and higher SSIM / PSNR are better; regions below; the best value of each column per "
             "scene is in bold. The paper's protocol (generator, full) and every other row follow.", "",
             "| Scene | Method | " + " | ".join(f"{_METRIC_NAMES[k]} ({r})" for k, r in cols) + " |",
             "|---|---" + "|---" * len(cols) + "|"]
    for s in info["sources"]:
        best = {(k, r): _best(summaries, s, mode, k, r) for k, r in cols}
        for m in ROW_ORDER:
            st = summaries[s]["methods"].get(mode, {}).get(m, {})
            cells = []
            for k, r in cols:
                text = _fmt(st.get(r, {}).get(k), 2 if k == "psnr" else 4)
                cells.append(f"**{text}**" if best[(k, r)] == m and text != "n/a" else text)
            lines.append(f"| {SOURCE_SHORT[s]} | {LABELS[m]} | " + " | ".join(cells) + " |")
    lines.append("")
    if comparisons is not None:
        lines += who_won_lines(comparisons, summaries, info)
    return lines


def _by_kind_lines(summaries: dict, info: dict) -> list[str]:
    """One table per kind of edit (``summarize``'s ``by_kind``: move, rotate, zoom, delete, occluder removed), every
    mode: L1 / PSNR on *all* and PSNR on *objects*."""
    lines: list[str] = []
    kinds = list(dict.fromkeys(k for s in info["sources"] for k in summaries[s].get("by_kind", {})))
    if kinds:
        lines += ["", "## By kind of edit", ""]
    for kind in kinds:
        counts = {s: summaries[s]["by_kind"].get(kind, {}).get("evaluated", 0) for s in info["sources"]}
        lines += ["", f"**{KIND_TITLES.get(kind, kind)}** ({max(counts.values())} entries):", "",
                  "| Scene | Mode | Method | L1 (all) | SSIM (all) | PSNR (all) | PSNR (objects) | mask IoU |",
                  "|---|---|---|---|---|---|---|---|"]
        for s in info["sources"]:
            for c in info["compose"]:
                methods = summaries[s].get("by_kind", {}).get(kind, {}).get("methods", {}).get(c, {})
                for m in ROW_ORDER:
                    st = methods.get(m, {})
                    lines.append(f"| {SOURCE_SHORT[s]} | {MODE_SHORT[c]} | {LABELS[m]} | "
                                 f"{_fmt(st.get('all', {}).get('l1'))} | {_fmt(st.get('all', {}).get('ssim'))} | "
                                 f"{_fmt(st.get('all', {}).get('psnr'), 2)} | "
                                 f"{_fmt(st.get('objects', {}).get('psnr'), 2)} | "
                                 f"{_fmt(st.get('layout', {}).get('mask_iou'), 3)} |")
    return lines


def _grid_rows(info: dict) -> list[tuple[str, str]]:
    """``(source, compose)`` of each example grid row, in the table's order."""
    return [(s, c) for s in info["sources"] for c in info["compose"]]


def examples_html(examples: list[dict], info: dict) -> str:
    """A page of example grids; ``examples``: ``{'file', 'key', 'metrics': {source: {compose: {method: ...}}}}`` per
    grid (one grid row per source scene and compose mode, :func:`_grid_rows`)."""
    rows = []
    for ex in examples:
        lines = []
        for s, c in _grid_rows(info):
            cells = [f"<td>{html.escape(SOURCE_SHORT[s])}, {html.escape(MODE_SHORT[c])}</td>"]
            for m in ("3d-sdn", "2d", "2d+"):
                v = ex["metrics"].get(s, {}).get(c, {}).get(m, {}).get("all", {})
                text = ", ".join(f"{k} {v[k]:.3f}" for k in ("lpips", "l1", "ssim") if k in v and math.isfinite(v[k]))
                cells.append(f"<td>{html.escape(LABELS[m])}: {html.escape(text or 'n/a')}</td>")
            lines.append(f"<tr>{''.join(cells)}</tr>")
        rows.append(f"<h3>{html.escape(ex['key'])}</h3>\n<img src=\"{html.escape(ex['file'])}\" alt=\"grid\">\n"
                    f"<table>{''.join(lines)}</table>")
    title = "sdn3d editing benchmark: examples"
    layout = "; ".join(f"row {i + 1}: {html.escape(SOURCE_LABELS[s])}, {html.escape(COMPOSE_LABELS[c])}"
                       for i, (s, c) in enumerate(_grid_rows(info)))
    gens = "; ".join(f"{html.escape(', '.join(LABELS[m] for m in ms))} drawn by {html.escape(g['checkpoint'])} "
                     f"({'with' if g['use_pose'] or g['use_normal'] else 'without'} pose / normal maps)"
                     for g, ms in _generator_methods(info["generators"]))
    return (f"<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>{title}</title>\n"
            "<style>body{font-family:sans-serif} img{image-rendering:pixelated;max-width:100%} "
            "td{padding:0 1em}</style></head><body>\n"
            f"<h1>{title}</h1>\n<p>{html.escape(info['benchmark'])}. Columns: source | target | 3D-SDN | 2D | 2D+ "
            f"({layout}; metrics on all edited regions; see <a href=\"table1.md\">table1.md</a>).</p>\n"
            f"<p>Generators: {gens}.</p>\n" + "\n".join(rows) + "\n</body></html>\n")


def _example_grid(images: dict[str, dict], rows: Sequence[tuple[str, str]]) -> np.ndarray:
    """``(H', W', 3)`` uint8: source | target | 3D-SDN | 2D | 2D+, one row per ``(source scene, mode)``, every
    panel titled (blank: no picture); ``images``: ``{source scene: EntryResult.images}``."""
    from sdn3d.visualize import titled_row

    first = next(iter(images.values()))
    blank = np.zeros_like(first["source"])
    lines = [titled_row([("source", first["source"]), ("target", first["target"])]
                        + [(f"{LABELS[m]}, {MODE_SHORT[c]}, {SOURCE_SHORT[s].split(':')[0]}",
                            images.get(s, {}).get(f"{c}:{m}", blank)) for m in ("3d-sdn", "2d", "2d+")])
             for s, c in rows]
    gap = np.full((6, lines[0].shape[1], 3), 255, np.uint8)
    return np.concatenate([x for line in lines for x in (line, gap)][:-1], 0)


def bench_modes(cfg: Any) -> tuple[Scene, list[Proposals]]:
    """``(scene, proposals)`` of the config as enums: ``scene`` (:class:`~sdn3d.evaluation.edit_benchmark.Scene`) and
    ``proposals`` (one value or a list of distinct ones of :data:`~sdn3d.evaluation.edit_benchmark.PROPOSALS`), the
    one place the benchmark reads them as strings.

    Raises:
        InputError: naming the setting and its values.
    """
    from omegaconf import ListConfig

    value = cfg.proposals
    proposals = [str(v) for v in value] if isinstance(value, (list, tuple, ListConfig)) else [str(value)]
    bad = [p for p in proposals if p not in PROPOSALS]
    if not proposals or bad or len(set(proposals)) != len(proposals):
        raise InputError(f"proposals must list distinct values of {list(PROPOSALS)} (semantic: the semantic branch's "
                         f"predictions; gt: the oracle), got {proposals}")
    scene = str(cfg.scene)
    if scene not in SCENES:
        raise InputError(f"scene must be one of {list(SCENES)} (derender: the source frame de-rendered; oracle: its "
                         f"ground-truth masks, semantics and geometry), got {scene!r}")
    return Scene(scene), [Proposals(p) for p in proposals]


def bench_passes(cfg: Any, base: dict) -> list[Any]:
    """One :class:`~sdn3d.evaluation.edit_benchmark.BenchSettings` per source scene the run evaluates: one per
    ``proposals`` value for ``scene=derender``, one for ``scene=oracle`` (proposals do not apply there)."""
    from sdn3d.evaluation.edit_benchmark import BenchSettings

    scene, proposals = bench_modes(cfg)
    if scene is Scene.ORACLE:
        return [BenchSettings(scene=scene, **base)]
    if Proposals.SEMANTIC in proposals and cfg.checkpoints.semantic is None:
        raise InputError(
            f"proposals={[p.value for p in proposals]} asks for the predicted row (3D-SDN on the semantic branch's "
            "masks and semantics, "
            "what a user gets) but checkpoints.semantic is null: give checkpoints.semantic=<the semantic branch's "
            "checkpoint>, or proposals=gt for the oracle row alone (ground-truth masks and semantics)")
    return [BenchSettings(scene=scene, proposals=p, **base) for p in proposals]


def _baseline_generator(cfg: Any, models: Any) -> tuple[Any, dict]:
    """``(TexturalRenderer or None, {method: generator_info})``: ``checkpoints.textural_2d`` draws 2D and 2D+."""
    from sdn3d.textural.renderer import TexturalRenderer

    ck = cfg.checkpoints
    main_gen = generator_info(ck.textural, models.textural.spec, "G")
    if ck.get("textural_2d") is None:
        return None, {m: main_gen for m in METHODS}
    path = Path(str(ck.textural_2d)).expanduser()
    if not path.is_file():
        raise InputError(f"checkpoints.textural_2d {str(ck.textural_2d)!r} does not exist")
    renderer = TexturalRenderer.from_checkpoint(path, map_location=cfg.device).to(cfg.device)
    if renderer.spec.num_classes != models.textural.spec.num_classes:
        raise InputError(f"checkpoints.textural_2d {str(path)!r} draws {renderer.spec.num_classes} classes, "
                         f"checkpoints.textural {models.textural.spec.num_classes}: train both on the same data")
    info = generator_info(ck.textural_2d, renderer.spec, "G-2D")
    if renderer.spec.use_pose or renderer.spec.use_normal:
        console.print(f"sdn3d-bench: warning: checkpoints.textural_2d {str(path)!r} takes pose / normal maps "
                      "(trained with model.use_pose / use_normal true): its 2D rows are not free of 3D knowledge")
    return renderer, {"3d-sdn": main_gen, "2d": info, "2d+": info}


def _proposal_fit(cfg: Any) -> FitSettings | None:
    """The proposals' test-time fit of ``fit_proposals`` (the default FitSettings), or None (the paper's protocol)."""
    return FitSettings() if cfg.fit_proposals else None


def _settings_base(cfg: Any, size: tuple[int, int]) -> dict:
    return dict(image_size=size, frame_size=tuple(cfg.frame_size), strict=bool(cfg.strict),
                pick_radius=cfg.pick_radius, modify_anchor=cfg.modify_anchor,
                min_pixels=int(cfg.geometric.min_pixels),
                fit=_proposal_fit(cfg), include_identity=bool(cfg.include_identity),
                limit=cfg.limit, examples=int(cfg.examples),
                compose=_compose_modes(cfg.compose), dilate_px=cfg.compose_dilate_px, feather_px=cfg.compose_feather_px,
                photo=PhotoSettings.from_mapping(cfg.get("photo")))


def _needed_branches(cfg: Any) -> tuple[str, ...]:
    """The branches the benchmark can not do without: the generator always, the geometric branch to de-render
    (``scene=derender``), the semantic branch for the predicted row (``proposals`` with ``semantic``)."""
    scene, proposals = bench_modes(cfg)
    if scene is Scene.ORACLE:
        return ("textural",)
    return ("semantic", "geometric", "textural") if Proposals.SEMANTIC in proposals else ("geometric", "textural")


def bench_checkpoints(cfg: Any) -> dict[str, dict | None]:
    """Per branch the file the benchmark loads (``{'path', 'from', ...}``, None: none): ``checkpoints.<branch>``
    where given, else with ``run=`` that directory's choice (:func:`sdn3d.runs.checkpoints_from_run`, printed on
    stderr).

    Raises:
        InputError: a bad ``run``, or ``run`` lacks a branch the benchmark needs (:func:`_needed_branches`).
    """
    if cfg.get("run") is None:
        return given_checkpoints(cfg.checkpoints)
    return checkpoints_from_run(cfg.run, cfg.checkpoints, _needed_branches(cfg), "sdn3d-bench", "the benchmark")


def _load_inputs(cfg: Any) -> tuple[Any, Path, Path, list, Any, list, dict]:
    """``(config, output dir, benchmark path, entries, source config, passes, checkpoints)`` after checking the
    settings; the config's ``checkpoints.<branch>`` are the files the benchmark loads (:func:`bench_checkpoints`)."""
    from omegaconf import OmegaConf

    from sdn3d.data.edit_benchmark import benchmark_path, load_edit_benchmark
    from sdn3d.data.sources import SourceConfig

    if cfg.threads:
        torch.set_num_threads(int(cfg.threads))
    source = SourceConfig.from_mapping(cfg.data)
    # benchmark=paper: the paper's file shipped in sdn3d.resources; otherwise a path.
    path = benchmark_path(str(cfg.benchmark)) if cfg.benchmark else Path(source.root) / "vkitti_edit_benchmark.json"
    out = check_output_dir(cfg.output_dir, MARKER, bool(cfg.overwrite), **output_rules(cfg, path))
    entries = load_edit_benchmark(path.expanduser())
    checkpoints = bench_checkpoints(cfg)
    cfg = OmegaConf.merge(cfg, {"checkpoints": {b: None if info is None else info["path"]
                                                for b, info in checkpoints.items()}})
    if cfg.checkpoints.textural is None:
        raise InputError("checkpoints.textural is required: every method is rendered by the textural generator")
    if cfg.device != "cpu" and not torch.cuda.is_available():
        raise InputError(f"device={cfg.device!r} but CUDA is not available")
    size = tuple(cfg.image_size) if cfg.image_size else source.image_size
    passes = bench_passes(cfg, _settings_base(cfg, size))
    if not cfg.get("allow_empty"):
        check_entries(entries, passes[0], path)
    return cfg, out, path, entries, source, passes, checkpoints


def output_rules(cfg: Any, benchmark: Path) -> dict[str, Any]:
    """:func:`sdn3d.io.check_output_dir`'s rules for ``output_dir`` (as ``sdn3d-edit``'s): an earlier result is
    replaced only if the directory holds nothing but the files its ``results.json`` lists (``outputs``), and never
    when it holds one of this run's inputs (the benchmark file, the dataset, a checkpoint, the run, LPIPS weights)."""
    given = {"benchmark": str(benchmark), "data.root": (cfg.get("data") or {}).get("root"), "run": cfg.get("run"),
             "lpips_weights": cfg.get("lpips_weights"),
             **{f"checkpoints.{b}": v for b, v in (cfg.get("checkpoints") or {}).items()}}
    return {"listed_in": "outputs", "inputs": {k: str(v) for k, v in given.items() if v is not None},
            "legacy": LEGACY_OUTPUTS}


def check_entries(entries: Sequence[Any], settings: Any, path: Path) -> None:
    """Refuse a benchmark with nothing to evaluate: no entry chosen (an empty list; with ``include_identity`` false,
    identity entries only; ``limit=0``), or every chosen entry's ``from`` and ``to`` points outside ``frame_size``
    (coordinates of another frame: each pick would be the object nearest a point off the picture).

    Raises:
        InputError: naming the benchmark file and what was found (``allow_empty=true`` evaluates it anyway).
    """
    chosen = [e for e in entries if settings.include_identity or not e.is_identity]
    if settings.limit is not None:
        chosen = chosen[: settings.limit]
    width, height = settings.frame_size

    def inside(uv: Any) -> bool:
        return uv is not None and -0.5 <= uv[0] <= width - 0.5 and -0.5 <= uv[1] <= height - 0.5

    usable = [e for e in chosen if e.is_identity or any(inside(op.from_uv) or inside(op.to_uv) for op in e.operations)]
    if usable:
        return
    if not chosen:
        why = ("it lists no entry" if not entries else
               f"none of its {len(entries)} entries is chosen (include_identity={settings.include_identity}, "
               f"limit={settings.limit})")
    else:
        why = (f"every point of its {len(chosen)} chosen entries lies outside the {width}x{height} frame "
               "(frame_size) its coordinates should refer to")
    raise InputError(f"benchmark {str(path)!r} has nothing to evaluate: {why}; give another benchmark (or the right "
                     "frame_size), or allow_empty=true to write empty tables anyway")


def _evaluate(cfg: Any, passes: list, entries: list, source: Any) -> tuple[dict, dict, dict]:
    """``({source scene: [EntryResult]}, {method: generator_info}, {'lpips': bool})``: every pass run."""
    from sdn3d.data.sources import read_source
    from sdn3d.evaluation.edit_benchmark import index_records, run_benchmark, source_name
    from sdn3d.models import Models
    from sdn3d.nets.lpips import load_lpips

    ck = cfg.checkpoints
    # The semantic branch only runs for the predicted row: do not load it otherwise.
    predicted = any(s.scene is Scene.DERENDER and s.proposals is Proposals.SEMANTIC for s in passes)
    semantic = ck.semantic if predicted else None
    geometric = ck.geometric if passes[0].scene is Scene.DERENDER else None
    models = Models.from_checkpoints(semantic, geometric, ck.textural, map_location=cfg.device,
                                     crop_size=cfg.geometric.crop_size, margin=cfg.geometric.margin,
                                     semantic_size=cfg.semantic.size, traffic=cfg.geometric.traffic)
    baseline, generators = _baseline_generator(cfg, models)
    if cfg.lpips_weights is not None and not Path(str(cfg.lpips_weights)).expanduser().is_file():
        raise InputError(f"lpips_weights {str(cfg.lpips_weights)!r} not found")
    lpips_net = load_lpips(cfg.lpips_weights)
    records = index_records(read_source(source))
    results = {}
    for settings in passes:
        name = source_name(settings)

        def progress(i: int, n: int, result: Any, name: str = name) -> None:
            status = "failed: " + "; ".join(result.errors.values()) if not result.metrics else "ok"
            console.print(f"[{SOURCE_SHORT[name]} {i}/{n}] entry {result.index} {result.key}: {status}", markup=False)

        results[name] = run_benchmark(entries, records, models, settings, lpips_net, progress, baseline)
    return results, generators, {"lpips": lpips_net is not None}


def evaluate_bench(cfg: Any) -> dict:
    """The evaluation half of :func:`run_bench`, writing nothing: ``{'results': {source scene: [EntryResult]},
    'generators', 'lpips', 'threads', 'wall_s'}`` for the config's passes (``proposals``). ``sdn3d-demo`` runs
    the predicted and the oracle pass in two processes at once and hands both to :func:`run_bench`."""
    cfg, _, _, entries, source, passes, _ = _load_inputs(cfg)
    t0 = time.perf_counter()
    results, generators, lpips = _evaluate(cfg, passes, entries, source)
    return {"results": results, "generators": generators, "lpips": lpips, "threads": torch.get_num_threads(),
            "wall_s": time.perf_counter() - t0}


def _merged(parts: Sequence[dict], passes: list) -> tuple[dict, dict, dict, float, int]:
    """``(results, generators, lpips, wall_s, threads)`` of :func:`evaluate_bench` parts, in the order of
    ``passes``; each pass must come from exactly one part."""
    from sdn3d.evaluation.edit_benchmark import source_name

    results: dict = {}
    for part in parts:
        twice = set(results) & set(part["results"])
        if twice:
            raise ValueError(f"benchmark parts evaluate {sorted(twice)} more than once")
        results |= part["results"]
    wanted = [source_name(s) for s in passes]
    if sorted(results) != sorted(wanted):
        raise ValueError(f"benchmark parts evaluate {sorted(results)}, the config asks for {wanted}")
    return ({name: results[name] for name in wanted}, parts[0]["generators"], parts[0]["lpips"],
            sum(p["wall_s"] for p in parts), max(p["threads"] for p in parts))


def run_bench(cfg: Any, parts: Sequence[dict] = ()) -> dict:
    """Run the benchmark of a composed ``conf/bench.yaml`` config; returns ``results.json``'s content. ``parts``:
    the passes already evaluated (:func:`evaluate_bench` of configs that split ``proposals``; ``sdn3d-demo``'s
    lanes): only written here, the same tables and example grids as one run's (``wall_s``: the parts' sum)."""
    from omegaconf import OmegaConf

    from sdn3d.data.synth.entry_report import benchmark_shortfall, counts_json, shortfall_lines
    from sdn3d.evaluation.edit_benchmark import source_name, summarize
    from sdn3d.io import write_json_atomic, write_png_atomic, write_text_atomic

    cfg, out, path, entries, source, passes, checkpoints = _load_inputs(cfg)
    short = benchmark_shortfall(path.expanduser(), entries)  # an unreadable manifest stops the run here
    t0 = time.perf_counter()
    threads = torch.get_num_threads()
    if parts:
        results, generators, lpips, wall_s, threads = _merged(parts, passes)
        t0 -= wall_s
    else:
        results, generators, lpips = _evaluate(cfg, passes, entries, source)
    # Once per run, with the scores (the demo's lanes do not warn; a run stopped by bad input says only why).
    for line in shortfall_lines(short, "sdn3d-bench"):
        console.print(line, markup=False, soft_wrap=True)
    summaries = {name: summarize(r) for name, r in results.items()}
    first = passes[0]
    sources = [source_name(s) for s in passes]
    info = {"benchmark": str(path), "data": f"{source.kind} at {source.root}", "image_size": list(first.image_size),
            "scene": first.scene, "sources": sources, "source_labels": {s: SOURCE_LABELS[s] for s in sources},
            "source_oracle": {s: s != Proposals.SEMANTIC for s in sources}, "generators": generators,
            "run": None if cfg.get("run") is None else str(cfg.run), "checkpoints": checkpoints,
            "device": str(cfg.device), "threads": threads, **lpips, "compose": list(first.compose),
            "dilate_px": first.dilate_px, "feather_px": first.feather_px,
            "fit_proposals": first.fit is not None and first.scene is Scene.DERENDER,
            "modify_anchor": str(first.modify_anchor), "benchmark_short": counts_json(short),
            "wall_s": time.perf_counter() - t0}
    entries_json = {name: [r.to_json() for r in rs] for name, rs in results.items()}
    groups = edited_car_groups([r for rs in entries_json.values() for r in rs])
    comparisons = paired_comparisons(entries_json, summaries, info, groups=groups)
    report = {"info": info, "config": OmegaConf.to_container(cfg, resolve=True), "summary": summaries,
              "comparisons": comparisons, "entries": entries_json}
    with staged_directory(out, MARKER, bool(cfg.overwrite), owned=True, **output_rules(cfg, path)) as tmp:
        examples = []
        for i, r in enumerate(results[sources[0]]):  # every pass has the same entries, in the same order
            images = {s: results[s][i].images for s in sources if results[s][i].images is not None}
            if not images:
                continue
            name = f"examples/{r.index:04d}.png"
            write_png_atomic(tmp / name, _example_grid(images, _grid_rows(info)))
            examples.append({"file": name, "key": r.key, "metrics": {s: results[s][i].metrics for s in sources}})
        write_text_atomic(tmp / "table1.md", table1_markdown(summaries, info, comparisons))
        write_text_atomic(tmp / "index.html", examples_html(examples, info))
        # every file written: what a later run may replace (the rest of a directory is the user's)
        report["outputs"] = sorted([*(e["file"] for e in examples), "table1.md", "index.html", MARKER])
        write_json_atomic(tmp / MARKER, report)
    return report


def _compose_modes(value: Any) -> tuple[str, ...]:
    """``compose``: one mode or a list of them (``photo``, ``full``, ``edited``), as given: BenchSettings parses
    them into :class:`~sdn3d.editing.appearance.PictureMode` (its error names every mode)."""
    from omegaconf import ListConfig

    return tuple(str(v) for v in value) if isinstance(value, (list, tuple, ListConfig)) else (str(value),)


def main(argv: Sequence[str] | None = None) -> int:
    """Console entry point: ``sdn3d-bench [overrides...]``; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if print_help_if_asked(argv, __doc__, "bench"):
        return 0
    return run_cli("bench", _main, argv)


def all_failed(report: dict) -> str | None:
    """A one-line reason when no entry of any source scene was evaluated (each failed), else None."""
    rows = [r for rs in report["entries"].values() for r in rs]
    if not rows or any(r["metrics"] for r in rows):
        return None
    first = next((f"entry {r['index']} {r['key']}: " + "; ".join(map(str, r["errors"].values()))
                  for r in rows if r["errors"]), "no error recorded")
    return f"every one of the {len(rows)} evaluations failed (first: {first[:300]})"


def run_counterfactual_bench(cfg: Any) -> dict:
    """``counterfactual=true``: the counterfactual benchmark (:mod:`sdn3d.evaluation.counterfactual`) on
    ``data.root``'s pairs; writes ``counterfactual.json`` and ``counterfactual.md`` into ``output_dir``."""
    from omegaconf import OmegaConf

    from sdn3d.data.counterfactual import load_pairs
    from sdn3d.data.vkitti1 import read_frames
    from sdn3d.derender import Models
    from sdn3d.evaluation import counterfactual as cf
    from sdn3d.evaluation.edit_benchmark import index_records
    from sdn3d.io import write_json_atomic, write_text_atomic

    reference = str(cfg.get("counterfactual_reference") or cf.REFERENCE)
    if reference not in cf.method_names():  # before anything is read or written
        raise InputError(f"counterfactual_reference must be one of {list(cf.method_names())}, got {reference!r}")
    root, marker = Path(str(cfg.data.root)).expanduser(), "counterfactual.json"
    rules = {"listed_in": "outputs", "inputs": {"data.root": str(root)}}
    out = check_output_dir(cfg.output_dir, marker, bool(cfg.overwrite), **rules)
    index = load_pairs(root)
    ck = (given_checkpoints(cfg.checkpoints) if cfg.get("run") is None else
          checkpoints_from_run(cfg.run, cfg.checkpoints, (), "sdn3d-bench", "the counterfactual benchmark"))
    paths = {b: None if info is None else info["path"] for b, info in ck.items()}
    models = (Models.from_checkpoints(paths.get("semantic"), paths.get("geometric"), paths.get("textural"),
                                      map_location=cfg.device, traffic=cfg.geometric.traffic)
              if any(paths.values()) else None)
    sources = cfg.get("counterfactual_sources") or ["oracle", *(["gt"] if paths.get("geometric") else []),
                                                    *(["semantic"] if paths.get("geometric") and paths.get("semantic")
                                                      else [])]
    settings = cf.CounterfactualSettings(sources=tuple(sources), fills=tuple(cfg.counterfactual_fills),
                                         photo=PhotoSettings.from_mapping({k: v for k, v in (cfg.get("photo") or {})
                                                                           .items() if k != "fill"}),
                                         min_pixels=int(cfg.geometric.min_pixels), limit=cfg.limit,
                                         fit=_proposal_fit(cfg),
                                         kinds=tuple(cfg.get("counterfactual_kinds") or ("turn", "delete")))
    t0 = time.perf_counter()
    results = cf.run_counterfactual(index, index_records(read_frames(root)), models, settings, lambda i, n, rows:
                                    console.print(f"[counterfactual {i}/{n}] {rows[0].key.split()[0]}", markup=False))
    names = cf.methods(settings, models is not None and models.textural is not None)
    summary, comps = cf.summarize(results, names), cf.comparisons(results, names, reference)
    info = {"data": f"pairs at {root}", "image_size": list(index.image_size), "sources": list(settings.sources),
            "source_labels": {s: cf.SOURCE_LABELS[s] for s in settings.sources}, "methods": list(names),
            "reference": reference, "checkpoints": ck, "wall_s": time.perf_counter() - t0}
    report = {"info": info, "config": OmegaConf.to_container(cfg, resolve=True), "summary": summary,
              "comparisons": comps, "pairs": [r.to_json() for r in results],
              "outputs": sorted(["counterfactual.md", marker])}
    with staged_directory(out, marker, bool(cfg.overwrite), owned=True, **rules) as tmp:
        write_text_atomic(tmp / "counterfactual.md", cf.counterfactual_markdown(summary, comps, info))
        write_json_atomic(tmp / marker, report)
    return report


def _main(argv: list[str]) -> int:
    cfg = compose_config(argv, "bench")
    if cfg.get("counterfactual"):
        report = run_counterfactual_bench(cfg)
        print((Path(str(cfg.output_dir)) / "counterfactual.md").read_text())
        return 0 if any(p["metrics"] for p in report["pairs"]) else 1
    report = run_bench(cfg)
    print(table1_markdown(report["summary"], report["info"], report.get("comparisons")))
    failed = all_failed(report)
    if failed is not None:
        print(f"sdn3d-bench: error: {failed}; results.json lists each entry's error", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
