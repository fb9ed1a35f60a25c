"""Resize an image as ``benchmarks/edit_call.py`` does (bicubic, RGB) and save it: ``prep_image.py IN OUT W H``."""

import sys

from PIL import Image

if __name__ == "__main__":
    src, dst, w, h = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    with Image.open(src) as im:
        im.convert("RGB").resize((w, h), Image.BICUBIC).save(dst)
