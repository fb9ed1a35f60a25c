"""Probe (not used by the code): glibc 2.36's ``cbrtf`` (sysdeps/ieee754/flt-32/s_cbrtf.c: a quadratic first guess
rounded to float, one Halley step in double, the exponent's third) emulated with vectorised NumPy, against
``np.cbrt`` (float32; on this machine, AVX2 without AVX-512, NumPy calls libm's cbrtf per value). The emulation
matches np.cbrt bit for bit over all float32 of both signs in [2^lo, 2^hi) and on random bit patterns, but it is
no faster than np.cbrt on the Lab conversion's (3, 466000) float32 (whole, or in chunks of 4k-64k values), so
PictureLab keeps np.cbrt.

    python cbrt_emulation.py LO HI      # e.g. -8 2: 168M values, about 20 s
"""

import sys
import time

import numpy as np

CBRT2 = 1.2599210498948731648
SQR_CBRT2 = 1.5874010519681994748
FACTOR = np.array([1.0 / SQR_CBRT2, 1.0 / CBRT2, 1.0, CBRT2, SQR_CBRT2])


def cbrtf(x: np.ndarray) -> np.ndarray:
    """glibc 2.36's cbrtf of float32 ``x``, value by value."""
    xm, xe = np.frexp(np.abs(x))
    xmd = xm.astype(np.float64)
    u = (0.492659620528969547 + (0.697570460207922770 - 0.191502161678719066 * xmd) * xmd).astype(np.float32)
    t2 = u * u * u
    ud, t2d = u.astype(np.float64), t2.astype(np.float64)
    q = np.sign(xe) * (np.abs(xe) // 3)  # C's xe / 3 and xe % 3 (truncating)
    r = xe - 3 * q
    ym = (ud * (t2d + 2.0 * xmd) / (2.0 * t2d + xmd) * FACTOR[2 + r]).astype(np.float32)
    out = np.ldexp(np.where(x > 0, ym, -ym), q)
    return np.where(((xe == 0) & ~(np.abs(x) > 0)) | ~np.isfinite(x), x + x, out)


def chunked(x: np.ndarray, n: int) -> np.ndarray:
    flat = x.reshape(-1)
    out = np.empty_like(flat)
    for s in range(0, len(flat), n):
        out[s:s + n] = cbrtf(flat[s:s + n])
    return out.reshape(x.shape)


def main() -> None:
    np.seterr(all="ignore")
    lo, hi = int(sys.argv[1]), int(sys.argv[2])
    t0, bad, n, step = time.time(), 0, 0, 1 << 22
    start, stop = int(np.float32(2.0 ** lo).view(np.uint32)), int(np.float32(2.0 ** hi).view(np.uint32))
    for s in range(start, stop, step):
        x = np.arange(s, min(s + step, stop), dtype=np.uint32).view(np.float32)
        for sign in (1, -1):
            xx = x * np.float32(sign)
            bad += int((cbrtf(xx).view(np.uint32) != np.cbrt(xx).view(np.uint32)).sum())
            n += len(xx)
    print(f"all float32 of both signs in [2^{lo}, 2^{hi}): {n} values, {bad} differ ({time.time() - t0:.1f} s)")
    special = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 1e-45, -1e-45, 1.1754942e-38, 3.4028235e38], np.float32)
    equal = (cbrtf(special).view(np.uint32) == np.cbrt(special).view(np.uint32)).all()
    print("special values' bits equal:", bool(equal))
    bits = np.random.default_rng(0).integers(0, 2**32, 20_000_000, dtype=np.uint64).astype(np.uint32)
    x = bits.view(np.float32)
    a, b = cbrtf(x), np.cbrt(x)
    same = (a.view(np.uint32) == b.view(np.uint32)) | (np.isnan(a) & np.isnan(b))
    print(f"random bit patterns: {int((~same).sum())} of {len(x)} differ")
    x = np.random.default_rng(1).random((3, 466000)).astype(np.float32)
    from sdn3d.editing.photo.road import _lab_of_linear

    best = min(_time(_lab_of_linear, x) for _ in range(5))
    print(f"(3, 466000) float32, the whole Lab conversion (road._lab_of_linear): {1000 * best:.1f} ms (least of 5)")
    for name, fn in (("np.cbrt", np.cbrt), ("emulation", cbrtf),
                     ("emulation, chunks of 4096", lambda a: chunked(a, 4096)),
                     ("emulation, chunks of 65536", lambda a: chunked(a, 65536))):
        best = min(_time(fn, x) for _ in range(5))
        print(f"(3, 466000) float32, {name}: {1000 * best:.1f} ms (least of 5)")


def _time(fn, x) -> float:
    t = time.perf_counter()
    fn(x)
    return time.perf_counter() - t


if __name__ == "__main__":
    main()
