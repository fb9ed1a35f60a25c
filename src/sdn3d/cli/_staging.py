"""All-or-nothing output directories for the CLIs (``sdn3d-edit``, ``sdn3d-bench``).

Every file goes into a temporary sibling directory that replaces the output directory only once
everything is written, so a failure leaves no partial output and an old result intact. An
existing non-empty directory is only replaced when it holds the tool's ``marker`` file (it is a
previous result of the same tool), never an unrelated folder.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["check_output_dir", "staged_directory"]


def check_output_dir(out: str | os.PathLike, marker: str, overwrite: bool) -> Path:
    """Raise ``FileExistsError`` if ``out`` may not be (re)written; returns it resolved."""
    out = Path(out).expanduser().resolve()
    if out.exists() and not out.is_dir():
        raise FileExistsError(f"output_dir {str(out)!r} exists and is not a directory")
    if out.is_dir() and any(out.iterdir()):
        if not overwrite:
            raise FileExistsError(f"output_dir {str(out)!r} is not empty (set overwrite=true to replace it)")
        if not (out / marker).is_file():
            raise FileExistsError(f"output_dir {str(out)!r} is not empty and holds no {marker} (not an earlier "
                                  "output of this tool): refusing to replace it; choose another output_dir")
    return out


@contextmanager
def staged_directory(out: str | os.PathLike, marker: str, overwrite: bool = True) -> Iterator[Path]:
    """Yield a temporary directory; on success it becomes ``out`` (write ``marker`` in it), on error it goes."""
    out = check_output_dir(out, marker, overwrite)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.parent))
    try:
        yield tmp
        if not (tmp / marker).is_file():
            raise RuntimeError(f"staged output misses its marker file {marker}")
        old = None
        if out.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
            os.rename(out, old / "tree")
        os.rename(tmp, out)
        if old is not None:
            shutil.rmtree(old)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
