// The photo appearance's nearest examples (sdn3d.editing.photo.nearest): for each query row, the indices of the k
// examples nearest it (squared Euclidean distance in float32), nearest first; of equal distances the lower index
// first. Plain C ABI, no torch headers; built on first use by sdn3d.native (g++ -O3 -march=native).
//
// The distances of one query to every example are computed into a buffer with the examples transposed (F, E), so
// the loop over examples is one vector loop (the part lookups' six features at once, the sum in a register; other
// counts a pass per feature, the same sums); the k best are then kept in a sorted array that a distance enters only
// when it beats the current k-th (most do not), a block of SKIP_BLOCK distances none of which does skipped after one
// vector count. Rows are split over `threads` std::threads in contiguous blocks: each row's result is its own, so any
// thread count gives the same bits.
//
// The grouped variant is for examples whose trailing T features take few distinct values (the part lookups' normals:
// one per template face the photo showed; 36-43 groups of 1,500 examples on the real frame's turns). Each group's
// trailing distance N_g is a lower bound of every member's distance (a member's sum adds the same squares to its
// leading features' sum, which is not negative; up to rounding, hence a margin of 1e-5). The groups are scanned in
// order of N_g, and the scan stops at the first whose N_g is beyond the k-th best distance so far; a group whose N_g
// plus the distance to the box of its members' leading features is beyond it is skipped. A member's distance
// is summed as the flat kernel sums it, and the k best are kept by (distance, example index), as the flat kernel's
// scan in index order keeps them: the same answer bit for bit. The caller orders the query rows by their trailing
// features (the scan reads each row and writes its answer in place, in that order), so that a row like the one
// before it reuses its groups' order; and each row starts from the k examples the row before it kept (a neighbour
// on the same face, as the part lookups ask them), so that the k-th best is near its final value from the first
// group on and most groups and blocks are skipped (a glass lookup's 16 nearest: about
// a third of the flat scan's time, docs/results/2026-12-02_cpu/session35/lead/nearest/). A group's members are offered
// to the k best only where they are at most the k-th best when their block of SKIP_BLOCK is looked at (a bit mask
// made in one vector pass, its set bits visited), and an example kept for the row is marked, not searched for among
// the k (a row's own k, met again in the groups, were half the offers of the 16 nearest): on the real frame's turns
// the grouped scan in about 0.78 of the time it took before (the same answer bit for bit;
// docs/results/2026-12-02_cpu/session37/perf/).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <thread>
#include <vector>

namespace {

constexpr int64_t SKIP_BLOCK = 32;  // distances counted at once against the k-th best
static_assert(SKIP_BLOCK <= 32, "the grouped scan holds a block's offers in 32 bits");

// d[j - lo] for j in [lo, hi): the squared distance of query q to example j of examples_t (F, E), its terms summed in
// feature order from 0. The six features of the part lookups in one pass (the sum held in a register), else a pass
// a feature: the same sums.
template <int FIXED>
void distances_fixed(const float* q, const float* examples_t, int64_t lo, int64_t hi, int64_t E, float* d) {
    float qf[FIXED];
    for (int f = 0; f < FIXED; ++f) qf[f] = q[f];
    for (int64_t j = lo; j < hi; ++j) {
        float s = 0.0f;
        for (int f = 0; f < FIXED; ++f) {
            const float t = qf[f] - examples_t[f * E + j];
            s += t * t;
        }
        d[j - lo] = s;
    }
}

// Always inlined: called apart, a group's few dozen members and a seed's one example paid a call and the test of F
// each time (the grouped scan on the real frame's turns in 0.88 of the time; the same sums, the answers checked).
inline __attribute__((always_inline)) void distances(const float* q, const float* examples_t, int64_t lo, int64_t hi,
                                                    int64_t E, int64_t F, float* d) {
    if (F == 6) {
        distances_fixed<6>(q, examples_t, lo, hi, E, d);
        return;
    }
    for (int64_t j = lo; j < hi; ++j) d[j - lo] = 0.0f;
    for (int64_t f = 0; f < F; ++f) {
        const float qf = q[f];
        const float* column = examples_t + f * E;
        for (int64_t j = lo; j < hi; ++j) {
            const float t = qf - column[j];
            d[j - lo] += t * t;
        }
    }
}

void rows_f32(const float* query, const float* examples_t, int64_t first, int64_t last, int64_t E, int64_t F,
              int64_t k, int64_t* out) {
    std::vector<float> dist(static_cast<size_t>(E));
    std::vector<float> best(static_cast<size_t>(k));
    std::vector<int64_t> index(static_cast<size_t>(k));
    for (int64_t r = first; r < last; ++r) {
        const float* q = query + r * F;
        float* d = dist.data();
        distances(q, examples_t, 0, E, E, F, d);
        int64_t kept = 0;
        float worst = INFINITY;
        for (int64_t j = 0; j < E; ++j) {
            if (kept == k && j % SKIP_BLOCK == 0 && j + SKIP_BLOCK <= E) {
                int below = 0;  // a block none of whose distances beats the k-th: skipped in one vector pass
                for (int64_t i = j; i < j + SKIP_BLOCK; ++i) below += d[i] < worst;
                if (!below) {
                    j += SKIP_BLOCK - 1;
                    continue;
                }
            }
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

// Keep `d` (example `j`) among the k best so far, ordered by (distance, example index); an example already kept is
// not kept twice: `in[j] == row` once it was kept for this row (one that was kept and pushed out again never passes
// the first test again: the k-th best only falls).
inline void keep(float d, int64_t j, int64_t k, int64_t& kept, float* best, int64_t* index, int64_t* in,
                 int64_t row) {
    if (kept == k && !(d < best[k - 1] || (d == best[k - 1] && j < index[k - 1]))) return;
    if (in[j] == row) return;
    in[j] = row;
    int64_t p = kept < k ? kept++ : k - 1;
    while (p > 0 && (best[p - 1] > d || (best[p - 1] == d && index[p - 1] > j))) {
        best[p] = best[p - 1];
        index[p] = index[p - 1];
        --p;
    }
    best[p] = d;
    index[p] = j;
}

void rows_grouped_f32(const float* query, const int64_t* rows, const float* examples_t, const int64_t* example_index,
                      const float* tails, const float* boxes, const int64_t* offsets, int64_t G, int64_t first,
                      int64_t last, int64_t E, int64_t F, int64_t S, int64_t k, int64_t* out) {
    const int64_t T = F - S;
    std::vector<float> dist(static_cast<size_t>(E));
    std::vector<float> tail_dist(static_cast<size_t>(G));
    std::vector<int64_t> order(static_cast<size_t>(G));
    std::vector<float> best(static_cast<size_t>(k));
    std::vector<int64_t> index(static_cast<size_t>(k));
    std::vector<int64_t> position(static_cast<size_t>(E));  // each example's place in the sorted arrays
    std::vector<int64_t> in(static_cast<size_t>(E), -1);  // the last row each example was kept for (keep)
    for (int64_t j = 0; j < E; ++j) position[example_index[j]] = j;
    for (int64_t r = first; r < last; ++r) {
        const float* q = query + rows[r] * F;
        int64_t kept = 0;
        if (r > first) {  // the row before's k best first: a neighbour's, near the k-th best from the start
            for (int64_t i = 0; i < k; ++i) {
                const int64_t j = position[out[rows[r - 1] * k + i]];
                float dj;
                distances(q, examples_t, j, j + 1, E, F, &dj);
                keep(dj, example_index[j], k, kept, best.data(), index.data(), in.data(), r);
            }
        }
        // rows sharing their trailing features (the caller sorts them so) share the groups' order
        if (r == first || !std::equal(q + S, q + F, query + rows[r - 1] * F + S)) {
            for (int64_t g = 0; g < G; ++g) {
                float n = 0.0f;
                for (int64_t t = 0; t < T; ++t) {
                    const float u = q[S + t] - tails[g * T + t];
                    n += u * u;
                }
                tail_dist[g] = n;
                order[g] = g;
            }
            std::sort(order.begin(), order.end(), [&](int64_t a, int64_t b) {
                return tail_dist[a] < tail_dist[b] || (tail_dist[a] == tail_dist[b] && a < b);
            });
        }
        for (int64_t g : order) {
            // every later group's members lie further (the margin: a member's sum may round its terms otherwise)
            if (kept == k && tail_dist[g] * (1.0f - 1e-5f) > best[k - 1]) break;
            if (kept == k) {  // the group's box of leading features: a tighter bound, for this group alone
                float bound = tail_dist[g];
                const float* low = boxes + g * 2 * S;
                for (int64_t f = 0; f < S; ++f) {
                    const float outside = std::max(std::max(low[f] - q[f], q[f] - low[S + f]), 0.0f);
                    bound += outside * outside;
                }
                if (bound * (1.0f - 1e-5f) > best[k - 1]) continue;
            }
            const int64_t lo = offsets[g], hi = offsets[g + 1];
            const float* d = dist.data();  // d[i]: example lo + i's distance
            distances(q, examples_t, lo, hi, E, F, dist.data());  // as the flat kernel sums them
            int64_t i = 0;
            for (; kept < k && i < hi - lo; ++i)  // the first row's first members: every one enters
                keep(d[i], example_index[lo + i], k, kept, best.data(), index.data(), in.data(), r);
            for (; i < hi - lo; i += SKIP_BLOCK) {
                // the block's members at most the k-th best (a tie may enter: a lower index) as bits, in one vector
                // pass; only those are offered (the k-th best only falls while the block is offered: the others
                // stay beyond it)
                const int64_t n = std::min<int64_t>(SKIP_BLOCK, hi - lo - i);
                const float worst = best[k - 1];
                uint32_t below = 0;
                for (int64_t b = 0; b < n; ++b) below |= static_cast<uint32_t>(d[i + b] <= worst) << b;
                while (below) {
                    const int64_t b = __builtin_ctz(below);
                    below &= below - 1;
                    keep(d[i + b], example_index[lo + i + b], k, kept, best.data(), index.data(), in.data(), r);
                }
            }
        }
        for (int64_t i = 0; i < k; ++i) out[rows[r] * k + i] = index[i];
    }
}

template <typename Rows>
void over_threads(int64_t Q, int threads, Rows rows) {
    const int64_t parts = std::max<int64_t>(1, std::min<int64_t>(threads, Q / 64));  // 64 rows at least a thread
    if (parts == 1) {
        rows(0, Q);
        return;
    }
    std::vector<std::thread> pool;
    const int64_t step = (Q + parts - 1) / parts;
    for (int64_t t = 1; t < parts; ++t) {
        const int64_t first = t * step, last = std::min(Q, first + step);
        if (first < last) pool.emplace_back(rows, first, last);
    }
    rows(0, std::min(Q, step));
    for (auto& worker : pool) worker.join();
}

}  // namespace

extern "C" {

int sdn3d_nearest_abi_version() { return 3; }

// query (Q, F), examples_t (F, E) float32, contiguous; out (Q, k) int64; 1 <= k <= E.
void sdn3d_nearest_f32(const float* query, const float* examples_t, int64_t Q, int64_t E, int64_t F, int64_t k,
                       int64_t* out, int threads) {
    over_threads(Q, threads, [=](int64_t first, int64_t last) {
        rows_f32(query, examples_t, first, last, E, F, k, out);
    });
}

// query (Q, F), scanned in the order rows (Q) (a permutation of its rows: the caller's, rows of equal trailing
// features one after another); the examples sorted by group: examples_t (F, E) transposed, example_index (E) each
// one's index in the caller's order, tails (G, F - S) each group's features from column S on, boxes (G, 2, S) each
// group's least and greatest leading features, offsets (G + 1) where each group's members start; out (Q, k) int64
// indices in the caller's order, row rows[r] of it written by the scan's r-th; 1 <= k <= E.
void sdn3d_nearest_grouped_f32(const float* query, const int64_t* rows, const float* examples_t,
                               const int64_t* example_index, const float* tails, const float* boxes,
                               const int64_t* offsets, int64_t G, int64_t Q, int64_t E, int64_t F, int64_t S,
                               int64_t k, int64_t* out, int threads) {
    over_threads(Q, threads, [=](int64_t first, int64_t last) {
        rows_grouped_f32(query, rows, examples_t, example_index, tails, boxes, offsets, G, first, last, E, F, S, k,
                         out);
    });
}

}  // extern "C"
