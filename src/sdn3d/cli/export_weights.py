"""``sdn3d-export-weights``: write the inference export of a branch's checkpoint (:mod:`sdn3d.inference_export`).

    sdn3d-export-weights CHECKPOINT [OUT]      # OUT defaults to inference.pt beside the checkpoint
    sdn3d-export-weights --run DIR             # each branch's checkpoint that run=DIR would use

An existing OUT is replaced only with ``--overwrite``, and a training checkpoint never (its run could no longer
resume); the default OUT replaces an earlier export there.

The export holds the predictor's weights, the module's hyper-parameters, the geometric run's crop size and
margin, a format version and the checkpoint's SHA-256; no optimizer, loop or callback state. It loads with
``torch.load(weights_only=True)`` and without Lightning, wherever a checkpoint is accepted
(``checkpoints.<branch>=`` of ``sdn3d-edit`` / ``sdn3d-bench``, ``*.from_checkpoint``); ``run=DIR`` uses
``<run>/checkpoints/inference.pt`` instead of the checkpoint when it was made from that checkpoint.
``sdn3d-train`` writes it at the end of every successful run; this tool is for older runs and other files.

Exit status: 0 done; 2 bad input (missing, unreadable or not a branch's checkpoint, an OUT that may not be
replaced; the message names it).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from sdn3d.cli._errors import run_argparse_cli
from sdn3d.errors import InputError

__all__ = ["main"]


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="sdn3d-export-weights",
                                     description="Write the inference export of a branch's checkpoint: the "
                                                 "predictor's weights only, loadable without Lightning.",
                                     epilog=__doc__.split("\n\n", 1)[1],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("checkpoint", nargs="?", help="a branch's Lightning checkpoint (sdn3d-train)")
    parser.add_argument("out", nargs="?", help="the export to write (default: inference.pt beside the checkpoint)")
    parser.add_argument("--run", help="a training output directory: export each branch's checkpoint run= would use")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace an existing OUT (never a training checkpoint; the default OUT, inference.pt "
                             "beside the checkpoint, replaces an earlier export without it)")
    return parser


def _size(path: Path) -> str:
    return f"{path.stat().st_size / 1e6:.1f} MB"


def _main(args: argparse.Namespace) -> int:
    from sdn3d.runs import export_checkpoint, find_run_checkpoints

    if (args.run is None) == (args.checkpoint is None):
        raise InputError("give a checkpoint (and optionally the output file) or --run DIR, not both")
    if args.run is not None:
        chosen, missing = find_run_checkpoints(args.run)
        jobs = [(Path(info["checkpoint"]), None) for info in chosen.values()]
        for branch, why in missing.items():
            print(f"sdn3d-export-weights: {branch}: nothing to export ({why})", file=sys.stderr)
    else:
        jobs = [(Path(args.checkpoint).expanduser(), args.out)]
    for checkpoint, out in jobs:
        written = export_checkpoint(checkpoint, out, args.overwrite)
        print(f"sdn3d-export-weights: {checkpoint} ({_size(checkpoint)}) -> {written} ({_size(written)})")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Console entry point; returns the exit status."""
    return run_argparse_cli("export-weights", _parser(), _main, argv)


if __name__ == "__main__":
    sys.exit(main())
