# ruff: noqa: INP001, E501
"""Compare two sdn3d-edit output directories file by file, byte for byte; edit.json is compared with its two
run-specific fields set aside (``timings_ms``, the wall times; ``config.output_dir``, where it was written), every
other field exactly. Prints one line per differing file and a summary; exit 1 if any differ."""

import json
import sys
from pathlib import Path


def _edit_record(path: Path) -> dict:
    record = json.loads(path.read_text())
    record.pop("timings_ms", None)
    record.get("config", {}).pop("output_dir", None)
    return record


def main() -> int:
    base, new = Path(sys.argv[1]), Path(sys.argv[2])
    names = sorted(p.relative_to(base).as_posix() for p in base.rglob("*") if p.is_file())
    others = sorted(p.relative_to(new).as_posix() for p in new.rglob("*") if p.is_file())
    differ = [] if names == others else [f"file lists differ: {sorted(set(names) ^ set(others))}"]
    for name in names:
        a, b = base / name, new / name
        if not b.is_file():
            continue
        same = _edit_record(a) == _edit_record(b) if name == "edit.json" else a.read_bytes() == b.read_bytes()
        if not same:
            differ.append(name)
    for line in differ:
        print("DIFFER", line)
    print(f"{len(names)} files ({', '.join(names)}); {len(differ)} differ (edit.json without timings_ms and config.output_dir)")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
