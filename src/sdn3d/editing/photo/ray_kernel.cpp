// The photo appearance's ray tracing (sdn3d.editing.photo.road._trace): for each ray, the first of the steps at
// which its point, rounded to a pixel, is a valid pixel of the picture. Plain C ABI, no torch headers; built on first
// use by sdn3d.native (g++ -O3 -march=native).
//
// The PyTorch path computes each point as (step * unit) + pix per coordinate in float32, a product then a sum (no
// fused multiply-add), rounds it half to even and looks it up in the mask padded with False; it looks at blocks of
// steps for every ray still searching. Here each ray walks its steps one by one and stops at its first hit (no block
// looked at past it), with the same float32 product, the same sum and the same rounding: the same answer bit for
// bit. GCC's default -ffp-contract=fast would fuse the product and the sum where -march=native has FMA (a different
// rounding): this file turns it off, and the product goes through an empty asm statement as well, which no compiler
// can fuse across.
#pragma GCC optimize("fp-contract=off")
#include <cmath>
#include <cstdint>

namespace {

// The float32 product, materialised: no multiply-add may absorb it.
inline float product(float a, float b) {
  float p = a * b;
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  asm("" : "+x"(p));
#elif defined(__GNUC__) && defined(__aarch64__)
  asm("" : "+w"(p));
#else
  volatile float v = p;
  p = v;
#endif
  return p;
}

}  // namespace

extern "C" {

int sdn3d_ray_abi_version() { return 2; }

// pix, unit: (n, 2) float32 (x, y); valid: (height, width) uint8 (0 / 1); steps: (count,) float32, increasing;
// limit: (n,) float32 or null (a step beyond a ray's limit does not count; nor does a NaN limit's any step).
// distance: (n,) float32 out, the first step that hits (steps[0] where none does); found: (n,) uint8 out.
void sdn3d_ray_trace_f32(const float* pix, const float* unit, const uint8_t* valid, int64_t height, int64_t width,
                         const float* steps, int64_t count, const float* limit, int64_t n, float* distance,
                         uint8_t* found) {
  for (int64_t i = 0; i < n; ++i) {
    const float px = pix[2 * i], py = pix[2 * i + 1], ux = unit[2 * i], uy = unit[2 * i + 1];
    float hit = steps[0];
    uint8_t ok = 0;
    for (int64_t j = 0; j < count; ++j) {
      const float st = steps[j];
      if (limit != nullptr && !(st <= limit[i])) break;  // steps increase: none further counts
      const float x = std::nearbyint(product(st, ux) + px);  // half to even, as torch's round
      const float y = std::nearbyint(product(st, uy) + py);
      if (!(x >= 0.0f && x < static_cast<float>(width) && y >= 0.0f && y < static_cast<float>(height))) continue;
      if (valid[static_cast<int64_t>(y) * width + static_cast<int64_t>(x)]) {
        hit = st;
        ok = 1;
        break;
      }
    }
    distance[i] = hit;
    found[i] = ok;
  }
}

// The points of sdn3d.editing.photo.road._along: for k = 0 .. span - 1 and each of the n rays, the point
// start + k * unit (float32, a product then a sum, as torch's start + k * unit) into points (span * n, 2), the k-th
// block of n rows for k, and whether it rounds (half to even) to a valid pixel inside the picture into ok
// (span * n,) uint8; the first point of each ray counts as valid (the caller's source).
void sdn3d_ray_along_f32(const float* start, const float* unit, const uint8_t* valid, int64_t height, int64_t width,
                         int64_t span, int64_t n, float* points, uint8_t* ok) {
  for (int64_t k = 0; k < span; ++k) {
    const float f = static_cast<float>(k);
    for (int64_t i = 0; i < n; ++i) {
      const float qx = product(f, unit[2 * i]) + start[2 * i];
      const float qy = product(f, unit[2 * i + 1]) + start[2 * i + 1];
      const int64_t row = k * n + i;
      points[2 * row] = qx;
      points[2 * row + 1] = qy;
      if (k == 0) {
        ok[row] = 1;
        continue;
      }
      const float x = std::nearbyint(qx), y = std::nearbyint(qy);
      ok[row] = (x >= 0.0f && x < static_cast<float>(width) && y >= 0.0f && y < static_cast<float>(height) &&
                 valid[static_cast<int64_t>(y) * width + static_cast<int64_t>(x)]) ? 1 : 0;
    }
  }
}

}  // extern "C"
