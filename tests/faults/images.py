"""Fault injection for input images: decompression bombs (small files declaring huge images).

    declared_size_png(path, width, height)    # a 1x1 PNG whose header claims width x height
    blank_png(path, width, height)            # a real all-black 1-bit PNG, streamed (a few kB per 100 MP)
"""

from __future__ import annotations

import io
import struct
import zlib
from pathlib import Path

from PIL import Image

__all__ = ["declared_size_png", "blank_png"]


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def declared_size_png(path: Path, width: int, height: int) -> Path:
    """A 1x1 RGB PNG written by Pillow, its IHDR patched to declare ``width x height`` (CRC fixed): the
    header is valid, the pixel data far too short (decoding it fails as truncated)."""
    buffer = io.BytesIO()
    Image.new("RGB", (1, 1)).save(buffer, format="PNG")
    data = bytearray(buffer.getvalue())
    assert data[12:16] == b"IHDR"
    data[16:24] = struct.pack(">II", width, height)
    data[29:33] = struct.pack(">I", zlib.crc32(bytes(data[12:29])) & 0xFFFFFFFF)
    path.write_bytes(bytes(data))
    return path


def blank_png(path: Path, width: int, height: int) -> Path:
    """A valid all-zero 1-bit greyscale PNG of ``width x height``, compressed row by row (never held
    whole in memory): it decodes, to ``width * height`` bytes in Pillow."""
    row = b"\x00" * (1 + (width + 7) // 8)  # filter type 0 + packed bits
    compressor, parts = zlib.compressobj(9), []
    for _ in range(height):
        parts.append(compressor.compress(row))
    parts.append(compressor.flush())
    header = struct.pack(">IIBBBBB", width, height, 1, 0, 0, 0, 0)  # bit depth 1, greyscale
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", header) + _chunk(b"IDAT", b"".join(parts))
                     + _chunk(b"IEND", b""))
    return path
