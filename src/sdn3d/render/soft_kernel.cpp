// Fused CPU kernel of sdn3d.render.soft's sparse soft silhouette (forward and analytic backward).
//
// The same math as the pure-PyTorch path in soft.py (_nearest_edge, _forward_chunk,
// _SoftSilhouetteFunction.backward) on the same (face, pixel) pairs (each face's box grown by the culling
// radius), without temporaries or window padding; the backward recomputes each pair's nearest edge instead of
// saving it. Plain C ABI (loaded with ctypes) and no torch headers, so g++ builds it in about a second.
//
// A face's box is only a few pixels a side at the fit's crop sizes, too small to vectorise over its pixels, so
// the SIMD lanes are faces: each mesh's faces with a non-empty box are sorted by box height, then width, and each
// group of kFaces faces walks the group's largest box together, one vector (Part) of kLanes faces at a time. A lane
// beyond its own box evaluates a throw-away pair (at its box's corner, so finite) that is neither added nor given a
// gradient; a Part whose every box ends before the pixel is skipped. The forward finds a window pixel's faces as
// bits (the faces whose box reaches its row, and-ed with those reaching its column) and adds their terms in
// ascending order, as a test of every face would (the scalar tests and index arithmetic of 16 faces at each of the
// window's pixels took a third of the forward's time; the edit call's forward 0.63 -> 0.53 CPU s). float32 groups
// 16 faces, in one 64-byte vector where the target has AVX-512, else in two 32-byte vectors of 8
// (SDN3D_SOFT_F32_LANES): without AVX-512 GCC lowers 64-byte vectors piecewise through the stack, 3-10x slower on
// an AVX2 machine (the edit call's fit took
// 10.9 CPU s instead of 3.9, docs/results/2026-11-29_cpu/session12/speed). The groups of 16 keep the order in which
// a pixel adds its faces' terms, so the results are the same to the bit with either. GCC's vector extensions keep
// the arithmetic in vectors on any target; float32's exp and log1p are Cephes' polynomials (within about 1 ulp,
// as PyTorch's own vectorised ones), float64 calls libm lane by lane (tests only).
//
// Every face accumulates its pairs in a fixed order and faces are visited in a fixed order, so results are
// deterministic, whatever the thread count (over_meshes). Inputs per face f (M faces, F per mesh): screen[f] = 3
// counter-clockwise vertices (x, y) in pixels; box[f] = (first column, first row, width, height), width * height
// == 0 for culled faces, which the kernel computes itself first (boxes: soft.py's _face_boxes, the same integers).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

namespace {

template <typename T>
struct Vec;
// float32 lanes per vector, a divisor of 16: 16 (one 64-byte vector a group) where the target has AVX-512's
// registers, else 8 (two 32-byte vectors, AVX2's). The results do not depend on it (the tests build the other).
#ifndef SDN3D_SOFT_F32_LANES
#if defined(__AVX512F__)
#define SDN3D_SOFT_F32_LANES 16
#else
#define SDN3D_SOFT_F32_LANES 8
#endif
#endif
template <>
struct Vec<float> {
    typedef float V __attribute__((vector_size(4 * SDN3D_SOFT_F32_LANES)));
    typedef int32_t I __attribute__((vector_size(4 * SDN3D_SOFT_F32_LANES)));
    static constexpr int kLanes = SDN3D_SOFT_F32_LANES;
    static constexpr int kFaces = 16;
    static_assert(kFaces % kLanes == 0, "a group is whole vectors");
};
template <>
struct Vec<double> {
    typedef double V __attribute__((vector_size(64)));
    typedef int64_t I __attribute__((vector_size(64)));
    static constexpr int kLanes = 8;
    static constexpr int kFaces = 8;
};

template <typename V>
inline V splat(typename std::remove_reference<decltype(V{}[0])>::type s) {
    V v;
    for (size_t j = 0; j < sizeof(V) / sizeof(s); ++j) v[j] = s;
    return v;
}

// The same bits as another vector type.
template <typename To, typename From>
inline To bit_cast(const From& from) {
    static_assert(sizeof(To) == sizeof(From), "bit_cast between vectors of one size");
    To to;
    std::memcpy(&to, &from, sizeof(To));
    return to;
}

// copysign(a, b) on the sign bit, as torch.copysign (so -0.0 counts as negative).
template <typename T>
inline typename Vec<T>::V copysign_v(typename Vec<T>::V a, typename Vec<T>::V b) {
    typedef typename Vec<T>::I I;
    typedef typename std::remove_reference<decltype(I{}[0])>::type S;
    const S sign = S(1) << (8 * sizeof(S) - 1);
    return bit_cast<typename Vec<T>::V>((bit_cast<I>(a) & ~sign) | (bit_cast<I>(b) & sign));
}

// exp (Cephes expf: range reduction by ln 2, degree-6 polynomial); 0 below -88.3 and inf above 88.4.
inline Vec<float>::V exp_v(Vec<float>::V x) {
    typedef Vec<float>::V V;
    typedef Vec<float>::I I;
    const V lo = splat<V>(-88.3762626647949f), hi = splat<V>(88.3762626647949f);
    x = x < lo ? lo : x;
    x = x > hi ? hi : x;
    V fx = x * 1.44269504088896341f + 0.5f;
    V tr = __builtin_convertvector(__builtin_convertvector(fx, I), V);  // toward zero
    fx = tr > fx ? tr - 1.0f : tr;                                     // floor
    x = x - fx * 0.693359375f;
    x = x - fx * -2.12194440e-4f;
    const V z = x * x;
    V y = 1.9875691500e-4f * x + 1.3981999507e-3f;
    y = y * x + 8.3334519073e-3f;
    y = y * x + 4.1665795894e-2f;
    y = y * x + 1.6666665459e-1f;
    y = y * x + 5.0000001201e-1f;
    y = y * z + x + 1.0f;
    I n = (__builtin_convertvector(fx, I) + 127) << 23;  // 2^fx (0 for fx = -127)
    return y * bit_cast<V>(n);
}

// log1p(u) for u in [0, 1] (Cephes logf on 1 + u, plus the rounding of 1 + u: log1p(u) = log(w) + (u - (w - 1)) / w).
inline Vec<float>::V log1p_unit_v(Vec<float>::V u) {
    typedef Vec<float>::V V;
    const V w = u + 1.0f;
    const V fix = (u - (w - 1.0f)) / w;
    const auto big = w > 1.41421356237f;
    const V e = big ? splat<V>(1.0f) : splat<V>(0.0f);
    const V y = (big ? w * 0.5f : w) - 1.0f;
    const V z = y * y;
    V p = 7.0376836292e-2f * y - 1.1514610310e-1f;
    p = p * y + 1.1676998740e-1f;
    p = p * y - 1.2420140846e-1f;
    p = p * y + 1.4249322787e-1f;
    p = p * y - 1.6668057665e-1f;
    p = p * y + 2.0000714765e-1f;
    p = p * y - 2.4999993993e-1f;
    p = p * y + 3.3333331174e-1f;
    p = p * y * z;
    p = p + e * -2.12194440e-4f;
    p = p - 0.5f * z;
    V r = y + p;
    r = r + e * 0.693359375f;
    return r + fix;
}

// torch.nn.functional.softplus (beta 1, threshold 20): max(x, 0) + log1p(exp(-|x|)) below the threshold.
inline Vec<float>::V softplus_v(Vec<float>::V x) {
    typedef Vec<float>::V V;
    const V zero = splat<V>(0.0f);
    const V ax = x < zero ? -x : x;
    const V soft = (x > zero ? x : zero) + log1p_unit_v(exp_v(-ax));
    return x > 20.0f ? x : soft;
}

inline Vec<float>::V sigmoid_v(Vec<float>::V x) { return 1.0f / (1.0f + exp_v(-x)); }

// float64 (tests, gradcheck): libm lane by lane, the PyTorch path's formulas.
inline Vec<double>::V softplus_v(Vec<double>::V x) {
    Vec<double>::V r;
    for (int j = 0; j < Vec<double>::kLanes; ++j) r[j] = x[j] > 20.0 ? x[j] : std::log1p(std::exp(x[j]));
    return r;
}

inline Vec<double>::V sigmoid_v(Vec<double>::V x) {
    Vec<double>::V r;
    for (int j = 0; j < Vec<double>::kLanes; ++j) r[j] = 1.0 / (1.0 + std::exp(-x[j]));
    return r;
}

// A group of faces, one per lane, and the per-lane edge tables of soft.py's _edge_tables: edge k runs from
// vertex k to vertex k + 1, (sx, sy) = (ex, ey) / max(|e|^2, area_eps).
template <typename T>
struct Group {
    typedef typename Vec<T>::V V;
    static constexpr int kLanes = Vec<T>::kLanes, kFaces = Vec<T>::kFaces, kParts = kFaces / kLanes;
    // One vector of faces: the edge tables of its kLanes faces and the window its boxes span.
    struct Part {
        int64_t win_w = 0, win_h = 0;
        V ax[3], ay[3], ex[3], ey[3], sx[3], sy[3], c0, r0, bw, bh;
    };
    int64_t win_w = 0, win_h = 0;
    int64_t face[kFaces], col0[kFaces], row0[kFaces], box_w[kFaces], box_h[kFaces], base[kFaces];
    Part part[kParts];

    void set_edges(const T* screen, T area_eps) {
        for (int j = 0; j < kFaces; ++j) {
            Part& p = part[j / kLanes];
            const int l = j % kLanes;
            const T* s = screen + 6 * face[j];
            for (int k = 0; k < 3; ++k) {
                const int n = (k + 1) % 3;
                const T ex_ = s[2 * n] - s[2 * k], ey_ = s[2 * n + 1] - s[2 * k + 1];
                T len2 = ex_ * ex_ + ey_ * ey_;
                len2 = len2 < area_eps ? area_eps : len2;
                p.ax[k][l] = s[2 * k], p.ay[k][l] = s[2 * k + 1], p.ex[k][l] = ex_, p.ey[k][l] = ey_;
                p.sx[k][l] = ex_ / len2, p.sy[k][l] = ey_ / len2;
            }
            p.c0[l] = T(col0[j]), p.r0[l] = T(row0[j]), p.bw[l] = T(box_w[j]), p.bh[l] = T(box_h[j]);
            p.win_w = std::max(p.win_w, box_w[j]);
            p.win_h = std::max(p.win_h, box_h[j]);
        }
    }
};

// Faces [face_lo, face_hi) with a non-empty box, sorted by (box height, box width), in groups of kLanes (the last
// one padded with empty boxes).
template <typename T>
std::vector<Group<T>> face_groups(const T* screen, const int64_t* box, int64_t face_lo, int64_t face_hi,
                                  int64_t faces_per_mesh, int64_t image_pixels, T area_eps) {
    constexpr int kFaces = Vec<T>::kFaces;
    // The faces in a stable sort by (height, width): two stable counting sorts, by width, then by height (box sides
    // are at most the image's, so a bucket per side; a comparison sort took most of this function's time).
    std::vector<int64_t> faces, order;
    int64_t max_w = 0, max_h = 0;
    for (int64_t f = face_lo; f < face_hi; ++f)
        if (box[4 * f + 2] > 0 && box[4 * f + 3] > 0) {
            faces.push_back(f);
            max_w = std::max(max_w, box[4 * f + 2]);
            max_h = std::max(max_h, box[4 * f + 3]);
        }
    order.resize(faces.size());
    std::vector<int64_t> first(std::max(max_w, max_h) + 2);
    for (const int side : {2, 3}) {  // width, then height
        std::fill(first.begin(), first.end(), 0);
        for (const int64_t f : faces) ++first[box[4 * f + side] + 1];
        for (size_t k = 1; k < first.size(); ++k) first[k] += first[k - 1];
        for (const int64_t f : faces) order[first[box[4 * f + side]]++] = f;
        faces.swap(order);
    }
    order.swap(faces);
    std::vector<Group<T>> groups((order.size() + kFaces - 1) / kFaces);
    for (size_t g = 0; g < groups.size(); ++g) {
        Group<T>& grp = groups[g];
        for (int j = 0; j < kFaces; ++j) {
            const size_t i = g * kFaces + j;
            const bool real = i < order.size();
            const int64_t f = real ? order[i] : order[g * kFaces];
            grp.face[j] = f;
            grp.col0[j] = box[4 * f];
            grp.row0[j] = box[4 * f + 1];
            grp.box_w[j] = real ? box[4 * f + 2] : 0;
            grp.box_h[j] = real ? box[4 * f + 3] : 0;
            grp.base[j] = (f / faces_per_mesh) * image_pixels;
            grp.win_w = std::max(grp.win_w, grp.box_w[j]);
            grp.win_h = std::max(grp.win_h, grp.box_h[j]);
        }
        grp.set_edges(screen, area_eps);
    }
    return groups;
}

// The pairs of each lane's face with its pixel at box offset (dc, dr) (its box's first pixel where the offset is
// beyond its box): x = copysign(d^2, min edge cross product) / sigma for the nearest edge (soft.py's
// _nearest_edge; ties pick the lower edge, as its 0 / 1 flags do), and for the backward that edge's one-hot
// flags, clamped segment parameter t and r = p - q.
template <typename T>
struct Pairs {
    typedef typename Vec<T>::V V;
    V px, py, x, on[3], t, rx, ry;

    Pairs(const typename Group<T>::Part& g, int64_t dc, int64_t dr, T inv_sigma) {
        const V zero = splat<V>(T(0)), one = splat<V>(T(1));
        const V vdc = splat<V>(T(dc)), vdr = splat<V>(T(dr));
        px = g.c0 + (vdc < g.bw ? vdc : zero);
        py = g.r0 + (vdr < g.bh ? vdr : zero);
        V d[3], c[3], tk[3], rxk[3], ryk[3];
        for (int k = 0; k < 3; ++k) {
            const V wx = px - g.ax[k], wy = py - g.ay[k];
            V s = wx * g.sx[k] + wy * g.sy[k];
            s = s < zero ? zero : s;
            s = s > one ? one : s;
            tk[k] = s;
            rxk[k] = wx - s * g.ex[k];
            ryk[k] = wy - s * g.ey[k];
            d[k] = rxk[k] * rxk[k] + ryk[k] * ryk[k];
            c[k] = g.ex[k] * wy - g.ey[k] * wx;
        }
        V cmin = c[0] < c[1] ? c[0] : c[1];
        cmin = cmin < c[2] ? cmin : c[2];
        const auto p1 = d[0] > d[1];  // edge 1 nearer than edge 0
        const V nearer = p1 ? d[1] : d[0];
        const auto p2 = nearer > d[2];  // edge 2 nearest
        const V best = p2 ? d[2] : nearer;
        on[2] = p2 ? one : zero;
        on[1] = p2 ? zero : (p1 ? one : zero);
        on[0] = (one - on[2]) - on[1];
        t = p2 ? tk[2] : (p1 ? tk[1] : tk[0]);
        rx = p2 ? rxk[2] : (p1 ? rxk[1] : rxk[0]);
        ry = p2 ? ryk[2] : (p1 ? ryk[1] : ryk[0]);
        x = copysign_v<T>(best, cmin) * inv_sigma;
    }
};

// Runs body(groups) for each mesh's face groups, on num_threads threads each taking whole meshes. A mesh's pixels
// receive only its own faces' terms, so each thread writes its own pixels; and as the groups are formed per mesh, a
// pixel adds its terms in the same order whatever the thread count: the result does not depend on it.
template <typename T, typename Body>
void over_meshes(const T* screen, const int64_t* box, int64_t num_faces, int64_t faces_per_mesh, int64_t pixels,
                 T area_eps, int num_threads, Body body) {
    const int64_t meshes = num_faces / faces_per_mesh;
    const int64_t parts = std::max<int64_t>(1, std::min<int64_t>(num_threads, meshes));
    auto run = [=](int64_t first, int64_t last) {
        for (int64_t m = first; m < last; ++m)
            body(face_groups(screen, box, m * faces_per_mesh, (m + 1) * faces_per_mesh, faces_per_mesh, pixels,
                             area_eps));
    };
    if (parts == 1) return run(int64_t(0), meshes);
    std::vector<std::thread> threads;
    for (int64_t p = 0; p < parts; ++p) threads.emplace_back(run, meshes * p / parts, meshes * (p + 1) / parts);
    for (std::thread& t : threads) t.join();
}

template <typename T>
void forward(const T* screen, const int64_t* box, int64_t num_faces, int64_t faces_per_mesh, int64_t height,
             int64_t width, T inv_sigma, T area_eps, T* log_keep, int num_threads) {
    over_meshes(screen, box, num_faces, faces_per_mesh, height * width, area_eps, num_threads,
                [=](const std::vector<Group<T>>& groups) {
        typedef typename Vec<T>::V V;
        constexpr int kLanes = Group<T>::kLanes, kParts = Group<T>::kParts, kFaces = Group<T>::kFaces;
        static_assert(kFaces <= 32, "a group's faces are the bits of a uint32_t");
        constexpr uint32_t kPart = (uint32_t(1) << kLanes) - 1;  // a part's lanes (of part 0)
        std::vector<uint32_t> rows_in, cols_in;
        for (const Group<T>& g : groups) {
            // Per window row and column, the faces (bits) whose box reaches it; each face's first pixel.
            rows_in.assign(g.win_h, 0);
            cols_in.assign(g.win_w, 0);
            T* first[kFaces];
            for (int j = 0; j < kFaces; ++j) {
                for (int64_t dr = 0; dr < g.box_h[j]; ++dr) rows_in[dr] |= uint32_t(1) << j;
                for (int64_t dc = 0; dc < g.box_w[j]; ++dc) cols_in[dc] |= uint32_t(1) << j;
                first[j] = log_keep + g.base[j] + g.row0[j] * width + g.col0[j];
            }
            for (int64_t dr = 0; dr < g.win_h; ++dr) {
                for (int64_t dc = 0; dc < g.win_w; ++dc) {
                    uint32_t in = rows_in[dr] & cols_in[dc];
                    if (in == 0) continue;
                    alignas(64) T term[kFaces];
                    for (int h = 0; h < kParts; ++h)  // a part with no face's box at (dc, dr) adds nothing
                        if (in & (kPart << (h * kLanes))) {
                            const V v = softplus_v(Pairs<T>(g.part[h], dc, dr, inv_sigma).x);
                            std::memcpy(term + h * kLanes, &v, sizeof(V));
                        }
                    const int64_t at = dr * width + dc;
                    for (; in != 0; in &= in - 1) {  // the faces in ascending order, as before
                        const int j = __builtin_ctz(in);
                        first[j][at] -= term[j];
                    }
                }
            }
        }
    });
}

// pixel_grad = dL/dA * (1 - A) * (-2 / sigma) per pixel; grad_screen (M, 3, 2) is overwritten. As soft.py's
// backward: dA/dx = (1 - A) D with D = sigmoid(x), dx/d(d^2) = delta / sigma, and for the nearest edge (a, b)
// d(d^2)/da = -2 (1 - t) r, d(d^2)/db = -2 t r (the envelope theorem).
template <typename T>
void backward(const T* screen, const int64_t* box, int64_t num_faces, int64_t faces_per_mesh, int64_t height,
              int64_t width, T inv_sigma, T area_eps, const T* pixel_grad, T* grad_screen, int num_threads) {
    typedef typename Vec<T>::V V;
    std::fill(grad_screen, grad_screen + 6 * num_faces, T(0));
    over_meshes(screen, box, num_faces, faces_per_mesh, height * width, area_eps, num_threads,
                [=](const std::vector<Group<T>>& groups) {
        constexpr int kLanes = Group<T>::kLanes, kParts = Group<T>::kParts;
        for (const Group<T>& g : groups) {
            for (int h = 0; h < kParts; ++h) {  // each face's pairs in the same order whatever the parts
                const typename Group<T>::Part& part = g.part[h];
                V grad[3][2];
                for (int v = 0; v < 3; ++v) grad[v][0] = grad[v][1] = splat<V>(T(0));
                for (int64_t dr = 0; dr < part.win_h; ++dr) {
                    for (int64_t dc = 0; dc < part.win_w; ++dc) {
                        const Pairs<T> p(part, dc, dr, inv_sigma);
                        V pg = splat<V>(T(0));  // 0 beyond a lane's box: no gradient
                        for (int l = 0; l < kLanes; ++l) {
                            const int j = h * kLanes + l;
                            if (dc < g.box_w[j] && dr < g.box_h[j])
                                pg[l] = pixel_grad[g.base[j] + (g.row0[j] + dr) * width + g.col0[j] + dc];
                        }
                        const V coef = pg * copysign_v<T>(sigmoid_v(p.x), p.x);
                        const V end = coef * p.t, start = coef - end;
                        for (int v = 0; v < 3; ++v) {  // vertex v starts edge v and ends edge v - 1
                            const V weight = p.on[v] * start + p.on[(v + 2) % 3] * end;
                            grad[v][0] += weight * p.rx;
                            grad[v][1] += weight * p.ry;
                        }
                    }
                }
                for (int l = 0; l < kLanes; ++l) {
                    const int j = h * kLanes + l;
                    if (g.box_w[j] > 0)
                        for (int v = 0; v < 3; ++v)
                            for (int i = 0; i < 2; ++i) grad_screen[6 * g.face[j] + 2 * v + i] = grad[v][i][l];
                }
            }
        }
    });
}

// Each face's pixel box grown by `radius`, box[f] = (first column, first row, width, height): soft.py's
// _face_boxes with the same float operations in the same order (its `lo - radius` is a subtraction in T), so the
// same integers; width and height are 0 where the face is culled (valid[f] == 0). Screen coordinates are finite
// (soft.py's projection replaces unusable vertices); a NaN all the same gives an empty box, not an undefined cast.
template <typename T>
void boxes(const T* screen, const uint8_t* valid, int64_t num_faces, int64_t height, int64_t width, T radius,
           int64_t* box) {
    const T size[2] = {T(width), T(height)};
    for (int64_t f = 0; f < num_faces; ++f) {
        const T* s = screen + 6 * f;
        int64_t* out = box + 4 * f;
        for (int a = 0; a < 2; ++a) {  // x: columns, y: rows
            const T lo = std::min(std::min(s[a], s[2 + a]), s[4 + a]);
            const T hi = std::max(std::max(s[a], s[2 + a]), s[4 + a]);
            if (!(lo == lo && hi == hi)) {
                out[a] = out[2 + a] = 0;
                continue;
            }
            T first = lo - radius;
            first = first < T(-1) ? T(-1) : first;  // clamp(min=-1), then minimum(size)
            first = first < size[a] ? first : size[a];
            first = std::ceil(first);
            first = first < T(0) ? T(0) : first;
            T last = hi + radius;
            last = last < T(-1) ? T(-1) : last;
            last = last < size[a] ? last : size[a];
            last = std::floor(last);
            last = last < size[a] - T(1) ? last : size[a] - T(1);
            const int64_t extent = int64_t(last) - int64_t(first) + 1;
            out[a] = int64_t(first);
            out[2 + a] = valid[f] && extent > 0 ? extent : 0;
        }
    }
}

}  // namespace

extern "C" {

int sdn3d_soft_abi_version() { return 4; }

int sdn3d_soft_f32_lanes() { return SDN3D_SOFT_F32_LANES; }

void sdn3d_soft_boxes_f32(const float* screen, const uint8_t* valid, int64_t num_faces, int64_t height, int64_t width,
                          double radius, int64_t* box) {
    boxes<float>(screen, valid, num_faces, height, width, float(radius), box);
}

void sdn3d_soft_boxes_f64(const double* screen, const uint8_t* valid, int64_t num_faces, int64_t height,
                          int64_t width, double radius, int64_t* box) {
    boxes<double>(screen, valid, num_faces, height, width, radius, box);
}

void sdn3d_soft_forward_f32(const float* screen, const int64_t* box, int64_t num_faces, int64_t faces_per_mesh,
                            int64_t height, int64_t width, double inv_sigma, double area_eps, float* log_keep,
                            int num_threads) {
    forward<float>(screen, box, num_faces, faces_per_mesh, height, width, float(inv_sigma), float(area_eps),
                   log_keep, num_threads);
}

void sdn3d_soft_forward_f64(const double* screen, const int64_t* box, int64_t num_faces, int64_t faces_per_mesh,
                            int64_t height, int64_t width, double inv_sigma, double area_eps, double* log_keep,
                            int num_threads) {
    forward<double>(screen, box, num_faces, faces_per_mesh, height, width, inv_sigma, area_eps, log_keep,
                    num_threads);
}

void sdn3d_soft_backward_f32(const float* screen, const int64_t* box, int64_t num_faces, int64_t faces_per_mesh,
                             int64_t height, int64_t width, double inv_sigma, double area_eps,
                             const float* pixel_grad, float* grad_screen, int num_threads) {
    backward<float>(screen, box, num_faces, faces_per_mesh, height, width, float(inv_sigma), float(area_eps),
                    pixel_grad, grad_screen, num_threads);
}

void sdn3d_soft_backward_f64(const double* screen, const int64_t* box, int64_t num_faces, int64_t faces_per_mesh,
                             int64_t height, int64_t width, double inv_sigma, double area_eps,
                             const double* pixel_grad, double* grad_screen, int num_threads) {
    backward<double>(screen, box, num_faces, faces_per_mesh, height, width, inv_sigma, area_eps, pixel_grad,
                     grad_screen, num_threads);
}

}  // extern "C"
