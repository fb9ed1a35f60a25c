// The photo appearance's nearest examples (sdn3d.editing.photo.nearest): for each query row, the indices of the k
// examples nearest it (squared Euclidean distance in float32), nearest first; of equal distances the lower index
// first. Plain C ABI, no torch headers; built on first use by sdn3d.native (g++ -O3 -march=native).
//
// The distances of one query to every example are computed into a buffer with the examples transposed (F, E), so
// the loop over examples is one vector loop per feature; the k best are then kept in a sorted array that a distance
// enters only when it beats the current k-th (most do not). Rows are split over `threads` std::threads in
// contiguous blocks: each row's result is its own, so any thread count gives the same bits.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <thread>
#include <vector>

namespace {

void rows_f32(const float* query, const float* examples_t, int64_t first, int64_t last, int64_t E, int64_t F,
              int64_t k, int64_t* out) {
    std::vector<float> dist(static_cast<size_t>(E));
    std::vector<float> best(static_cast<size_t>(k));
    std::vector<int64_t> index(static_cast<size_t>(k));
    for (int64_t r = first; r < last; ++r) {
        const float* q = query + r * F;
        float* d = dist.data();
        for (int64_t j = 0; j < E; ++j) d[j] = 0.0f;
        for (int64_t f = 0; f < F; ++f) {
            const float qf = q[f];
            const float* column = examples_t + f * E;
            for (int64_t j = 0; j < E; ++j) {
                const float t = qf - column[j];
                d[j] += t * t;
            }
        }
        int64_t kept = 0;
        float worst = INFINITY;
        for (int64_t j = 0; j < E; ++j) {
            const float dj = d[j];
            if (kept < k || dj < worst) {  // a tie with the k-th keeps the lower index
                int64_t p = kept < k ? kept++ : k - 1;
                while (p > 0 && best[p - 1] > dj) {  // after any equal distance: the lower index stays first
                    best[p] = best[p - 1];
                    index[p] = index[p - 1];
                    --p;
                }
                best[p] = dj;
                index[p] = j;
                worst = kept < k ? INFINITY : best[k - 1];
            }
        }
        for (int64_t i = 0; i < k; ++i) out[r * k + i] = index[i];
    }
}

}  // namespace

extern "C" {

int sdn3d_nearest_abi_version() { return 1; }

// query (Q, F), examples_t (F, E) float32, contiguous; out (Q, k) int64; 1 <= k <= E.
void sdn3d_nearest_f32(const float* query, const float* examples_t, int64_t Q, int64_t E, int64_t F, int64_t k,
                       int64_t* out, int threads) {
    const int64_t parts = std::max<int64_t>(1, std::min<int64_t>(threads, Q / 64));  // 64 rows at least a thread
    if (parts == 1) {
        rows_f32(query, examples_t, 0, Q, E, F, k, out);
        return;
    }
    std::vector<std::thread> pool;
    const int64_t step = (Q + parts - 1) / parts;
    for (int64_t t = 1; t < parts; ++t) {
        const int64_t first = t * step, last = std::min(Q, first + step);
        if (first < last) pool.emplace_back(rows_f32, query, examples_t, first, last, E, F, k, out);
    }
    rows_f32(query, examples_t, 0, std::min(Q, step), E, F, k, out);
    for (auto& worker : pool) worker.join();
}

}  // extern "C"
