"""Compare two or more code trees' output directories of the same sdn3d-edit calls (same_outputs.sh), file by file.

    python compare_outputs.py OUT NAME NAME...

Every file of OUT/<first name>/<call>/ against the same file of the others: bytes equal, or, for JSON, equal apart
from the fields a run records about itself (timings, the output directory, the input paths of the code tree); a
file one side lacks counts as a difference. Prints one line per call and a total; exit 1 on any difference.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

#: JSON keys whose values describe the run, not its result.
RUN_KEYS = {"timings_ms", "derender_ms", "edit_ms", "render_ms", "photo_ms", "compose_ms", "output_dir"}


def _strip(value: object) -> object:
    if isinstance(value, dict):
        return {k: _strip(v) for k, v in value.items() if k not in RUN_KEYS}
    if isinstance(value, list):
        return [_strip(v) for v in value]
    return value


def main() -> int:
    out, names = Path(sys.argv[1]), sys.argv[2:]
    first, bad, total = out / names[0], 0, 0
    for call in sorted(p for p in first.iterdir() if p.is_dir()):
        files = sorted(p.relative_to(call) for p in call.rglob("*") if p.is_file())
        for other in names[1:]:
            there = out / other / call.name
            theirs = sorted(p.relative_to(there) for p in there.rglob("*") if p.is_file())
            diffs = [str(f) for f in sorted(set(files) ^ set(theirs))]
            for f in files:
                if f not in theirs:
                    continue
                a, b = (call / f).read_bytes(), (there / f).read_bytes()
                if a == b:
                    continue
                if f.suffix == ".json" and _strip(json.loads(a)) == _strip(json.loads(b)):
                    continue
                diffs.append(str(f))
            total += len(files)
            bad += len(diffs)
            print(f"{call.name}: {names[0]} vs {other}: {len(files) - len(diffs)} of {len(files)} files the same"
                  + (f"; differ: {', '.join(diffs)}" if diffs else ""))
    print(f"all: {total - bad} of {total} files the same")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
