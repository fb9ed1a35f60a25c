"""``sdn3d-bench``: the editing benchmark (paper Table 1), see :mod:`sdn3d.evaluation.edit_benchmark`.

Configuration ``conf/bench.yaml`` (Hydra overrides as arguments). Outputs, written all at once:

    results.json     settings, summary (means per compose mode / method / region / metric, latency), every entry
    table1.md        the paper's Table 1 layout (LPIPS whole / all / largest) plus L1, SSIM, PSNR, one row per
                     method and compose mode: ``full`` = the generator's whole picture (the paper's protocol),
                     ``edited`` = the source outside the method's edit region (what ``sdn3d-edit`` gives a user)
    index.html       example grids (source | target | 3D-SDN | 2D | 2D+, one row per compose mode) with metrics
    examples/*.png   the grids

Exit status: 0 done; 2 bad input (missing benchmark / checkpoint, no matching frames; nothing written).
"""

from __future__ import annotations

import html
import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import torch
from rich.console import Console

from sdn3d.cli._config import CONFIG_DIR, compose_config
from sdn3d.cli._errors import run_cli
from sdn3d.errors import InputError
from sdn3d.evaluation.edit_benchmark import REGIONS
from sdn3d.io import check_output_dir, staged_directory

__all__ = ["main", "run_bench", "table1_markdown", "examples_html"]

MARKER = "results.json"
LABELS = {"2d": "2D", "2d+": "2D+", "3d-sdn": "3D-SDN (ours)"}
ROW_ORDER = ("2d", "2d+", "3d-sdn")  # the paper's row order
COMPOSE_LABELS = {"full": "full (paper protocol)", "edited": "edited (what a user gets)"}
console = Console(stderr=True)


def _fmt(stat: dict | None, digits: int = 4) -> str:
    if not stat or stat.get("n", 0) == 0 or not math.isfinite(stat["mean"]):
        return "n/a"
    return f"{stat['mean']:.{digits}f}"


def _rows(summary: dict, info: dict) -> list[tuple[str, str, dict]]:
    """``(method, compose, {region: {metric: stat}})`` per table row: every compose mode, the paper's row order."""
    methods = summary["methods"]
    return [(m, c, methods.get(c, {}).get(m, {})) for c in info["compose"] for m in ROW_ORDER]


def table1_markdown(summary: dict, info: dict) -> str:
    """The paper's Table 1 layout (rows 2D, 2D+, 3D-SDN per compose mode) from
    :func:`sdn3d.evaluation.edit_benchmark.summarize` output."""
    rows = _rows(summary, info)
    has_lpips = any("lpips" in stats.get("whole", {}) for _, _, stats in rows)
    lines = ["# Editing benchmark (3D-SDN Table 1 layout)", "",
             f"{summary['evaluated']} of {summary['entries']} entries evaluated on `{info['benchmark']}` "
             f"({info['data']}), working size {info['image_size'][0]}x{info['image_size'][1]}, source scene: "
             f"{info['scene']}" + (f" (proposals: {info['proposals']})" if info["scene"] == "derender" else "")
             + ". All methods are drawn by the same textural generator. Lower LPIPS / L1 and higher SSIM / "
             "PSNR are better; *all* = the union of the edited objects' source and target regions, *largest* "
             "= the largest edited object's target box (crop).", "",
             "Compose *full* = the generator's whole picture (the paper's protocol); compose *edited* = the source "
             "frame with only the method's edit region (its edited objects' footprints and changed pixels, dilated "
             f"{info['dilate_px']} px, feathered {info['feather_px']} px) redrawn, at the working size: what "
             "`sdn3d-edit` gives a user.", ""]
    lines += ["| Method | Compose | LPIPS (whole) | LPIPS (all) | LPIPS (largest) |", "|---|---|---|---|---|"]
    for m, c, stats in rows:
        cells = [_fmt(stats.get(r, {}).get("lpips")) for r in REGIONS]
        lines.append(f"| {LABELS[m]} | {COMPOSE_LABELS[c]} | " + " | ".join(cells) + " |")
    if not has_lpips:
        lines += ["", "LPIPS: n/a, no LPIPS weights were given (`lpips_weights=`, see sdn3d.nets.lpips)."]
    lines += ["", "| Method | Compose | " + " | ".join(f"{k} ({r})" for k in ("L1", "SSIM", "PSNR") for r in REGIONS)
              + " |", "|---" * 11 + "|"]
    for m, c, stats in rows:
        cells = [_fmt(stats.get(r, {}).get(k), 2 if k == "psnr" else 4)
                 for k in ("l1", "ssim", "psnr") for r in REGIONS]
        lines.append(f"| {LABELS[m]} | {COMPOSE_LABELS[c]} | " + " | ".join(cells) + " |")
    lines += ["", "Layout diagnostic (not in the paper; needs no trained generator): mean IoU between where each "
                  "method draws the edited objects and where the target frame shows them.", "",
              "| Method | edited-object mask IoU |", "|---|---|"]
    lines += [f"| {LABELS[m]} | {_fmt(stats.get('layout', {}).get('mask_iou'), 3)} |"
              for m, c, stats in rows if c == info["compose"][0]]
    lat = summary["latency_ms"]
    compose = (f"; compose edited adds {_fmt(lat['compose'], 1)} ms" if "edited" in info["compose"] else "")
    lines += ["", f"3D-SDN latency per edit (de-render + edit + render, {info['device']}, "
                  f"{info['threads']} threads): mean {_fmt(lat['total'], 0)} ms (de-render {_fmt(lat['derender'], 0)}, "
                  f"edit {_fmt(lat['edit'], 0)}, render {_fmt(lat['render'], 0)} ms{compose}).",
              "", "Entries that failed per method: " + ", ".join(f"{LABELS[m]} {summary['failed'][m]}"
                                                                  for m in ROW_ORDER) + "."]
    return "\n".join(lines) + "\n"


def examples_html(examples: list[dict], info: dict) -> str:
    """A page of example grids; ``examples``: ``{'file', 'key', 'metrics'}`` per grid (one grid row per compose
    mode of ``info['compose']``)."""
    rows = []
    for ex in examples:
        lines = []
        for c in info["compose"]:
            cells = [f"<td>compose {html.escape(c)}</td>"]
            for m in ("3d-sdn", "2d", "2d+"):
                v = ex["metrics"].get(c, {}).get(m, {}).get("all", {})
                text = ", ".join(f"{k} {v[k]:.3f}" for k in ("lpips", "l1", "ssim") if k in v and math.isfinite(v[k]))
                cells.append(f"<td>{html.escape(LABELS[m])}: {html.escape(text or 'n/a')}</td>")
            lines.append(f"<tr>{''.join(cells)}</tr>")
        rows.append(f"<h3>{html.escape(ex['key'])}</h3>\n<img src=\"{html.escape(ex['file'])}\" alt=\"grid\">\n"
                    f"<table>{''.join(lines)}</table>")
    title = "sdn3d editing benchmark: examples"
    modes = "; ".join(f"row {i + 1}: compose {html.escape(COMPOSE_LABELS[c])}" for i, c in enumerate(info["compose"]))
    return (f"<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>{title}</title>\n"
            "<style>body{font-family:sans-serif} img{image-rendering:pixelated;max-width:100%} "
            "td{padding:0 1em}</style></head><body>\n"
            f"<h1>{title}</h1>\n<p>{html.escape(info['benchmark'])}, scene: {html.escape(info['scene'])}. "
            f"Columns: source | target | 3D-SDN | 2D | 2D+ ({modes}; metrics on all edited regions; "
            "see <a href=\"table1.md\">table1.md</a>).</p>\n" + "\n".join(rows) + "\n</body></html>\n")


def _example_grid(images: dict, modes: Sequence[str]) -> np.ndarray:
    """``(H', W', 3)`` uint8: source | target | 3D-SDN | 2D | 2D+, one row per compose mode (blank: no picture)."""
    from sdn3d.visualize import hstack_panels

    blank = np.zeros_like(images["source"])
    lines = [hstack_panels([images["source"], images["target"]]
                           + [images.get(f"{c}:{m}", blank) for m in ("3d-sdn", "2d", "2d+")]) for c in modes]
    gap = np.full((4, lines[0].shape[1], 3), 255, np.uint8)
    return np.concatenate([x for line in lines for x in (line, gap)][:-1], 0)


def run_bench(cfg: Any) -> dict:
    """Run the benchmark of a composed ``conf/bench.yaml`` config; returns ``results.json``'s content."""
    from omegaconf import OmegaConf

    from sdn3d.data.edit_benchmark import benchmark_path, load_edit_benchmark
    from sdn3d.data.sources import SourceConfig, read_source
    from sdn3d.derender import Models
    from sdn3d.evaluation.edit_benchmark import BenchSettings, index_records, run_benchmark, summarize
    from sdn3d.io import write_json_atomic, write_png_atomic, write_text_atomic
    from sdn3d.nets.lpips import load_lpips

    if cfg.threads:
        torch.set_num_threads(int(cfg.threads))
    out = check_output_dir(cfg.output_dir, MARKER, bool(cfg.overwrite))
    source = SourceConfig.from_mapping(cfg.data)
    # benchmark=paper: the paper's file shipped in sdn3d.resources; otherwise a path.
    path = benchmark_path(str(cfg.benchmark)) if cfg.benchmark else Path(source.root) / "vkitti_edit_benchmark.json"
    entries = load_edit_benchmark(path.expanduser())
    if cfg.checkpoints.textural is None:
        raise InputError("checkpoints.textural is required: every method is rendered by the textural generator")
    if cfg.device != "cpu" and not torch.cuda.is_available():
        raise InputError(f"device={cfg.device!r} but CUDA is not available")
    size = tuple(cfg.image_size) if cfg.image_size else source.image_size
    settings = BenchSettings(image_size=size, scene=str(cfg.scene), proposals=str(cfg.proposals),
                             frame_size=tuple(cfg.frame_size), strict=bool(cfg.strict), pick_radius=cfg.pick_radius,
                             min_pixels=int(cfg.geometric.min_pixels), include_identity=bool(cfg.include_identity),
                             limit=cfg.limit, examples=int(cfg.examples), compose=_compose_modes(cfg.compose),
                             dilate_px=cfg.compose_dilate_px, feather_px=cfg.compose_feather_px)
    ck = cfg.checkpoints
    # The semantic branch only runs for derender proposals other than 'gt': do not load it otherwise.
    semantic = ck.semantic if settings.scene == "derender" and settings.proposals != "gt" else None
    geometric = ck.geometric if settings.scene == "derender" else None
    models = Models.from_checkpoints(semantic, geometric, ck.textural, map_location=cfg.device,
                                     crop_size=cfg.geometric.crop_size, margin=cfg.geometric.margin)
    if cfg.lpips_weights is not None and not Path(str(cfg.lpips_weights)).expanduser().is_file():
        raise InputError(f"lpips_weights {str(cfg.lpips_weights)!r} not found")
    lpips_net = load_lpips(cfg.lpips_weights)
    records = index_records(read_source(source))

    def progress(i: int, n: int, result: Any) -> None:
        status = "failed: " + "; ".join(result.errors.values()) if not result.metrics else "ok"
        console.print(f"[{i}/{n}] entry {result.index} {result.key}: {status}")

    t0 = time.perf_counter()
    results = run_benchmark(entries, records, models, settings, lpips_net, progress)
    summary = summarize(results)
    info = {"benchmark": str(path), "data": f"{source.kind} at {source.root}", "image_size": list(settings.image_size),
            "scene": settings.scene, "proposals": settings.proposals, "device": str(cfg.device),
            "threads": torch.get_num_threads(), "lpips": lpips_net is not None, "compose": list(settings.compose),
            "dilate_px": settings.dilate_px, "feather_px": settings.feather_px, "wall_s": time.perf_counter() - t0}
    report = {"info": info, "config": OmegaConf.to_container(cfg, resolve=True), "summary": summary,
              "entries": [r.to_json() for r in results]}
    with staged_directory(out, MARKER, bool(cfg.overwrite)) as tmp:
        examples = []
        for r in results:
            if r.images is None:
                continue
            name = f"examples/{r.index:04d}.png"
            write_png_atomic(tmp / name, _example_grid(r.images, settings.compose))
            examples.append({"file": name, "key": r.key, "metrics": r.metrics})
        write_text_atomic(tmp / "table1.md", table1_markdown(summary, info))
        write_text_atomic(tmp / "index.html", examples_html(examples, info))
        write_json_atomic(tmp / MARKER, report)
    return report


def _compose_modes(value: Any) -> tuple[str, ...]:
    """``compose``: one mode or a list of them (``full``, ``edited``)."""
    from omegaconf import ListConfig

    return tuple(str(v) for v in value) if isinstance(value, (list, tuple, ListConfig)) else (str(value),)


def main(argv: Sequence[str] | None = None) -> int:
    """Console entry point: ``sdn3d-bench [overrides...]``; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if any(a in ("-h", "--help") for a in argv):
        print(__doc__)
        print(Path(CONFIG_DIR, "bench.yaml").read_text())
        return 0
    return run_cli("bench", _main, argv)


def _main(argv: list[str]) -> int:
    report = run_bench(compose_config(argv, "bench"))
    print(table1_markdown(report["summary"], report["info"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
