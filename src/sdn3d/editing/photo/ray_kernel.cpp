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

int sdn3d_ray_abi_version() { return 1; }

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

}  // extern "C"
