#include KERNEL
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
template <typename T> std::vector<T> load(const std::string& p) {
    std::ifstream f(p, std::ios::binary | std::ios::ate); size_t n = f.tellg(); f.seekg(0);
    std::vector<T> v(n / sizeof(T)); f.read((char*)v.data(), n); return v; }
int main(int argc, char** argv) {
    for (std::string size : {"32", "64"}) {
        std::string base = "/tmp/s12data/speed/k_";
        std::ifstream mf(base + "forward_" + size + ".meta"); long M, fpm, H, W; double inv; mf >> M >> fpm >> H >> W >> inv;
        auto screen = load<float>(base + "forward_" + size + ".screen"); auto box = load<int64_t>(base + "forward_" + size + ".box");
        auto ref = load<float>(base + "forward_" + size + ".out");
        std::vector<float> out(ref.size());
        int reps = 5; double best = 1e9;
        for (int r = 0; r < reps; ++r) {
            std::fill(out.begin(), out.end(), 0.f);
            auto t = std::chrono::steady_clock::now();
            sdn3d_soft_forward_f32(screen.data(), box.data(), M, fpm, H, W, inv, 1e-10, out.data(), 1);
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
        }
        size_t diff = 0; for (size_t i = 0; i < out.size(); ++i) diff += std::memcmp(&out[i], &ref[i], 4) != 0;
        printf("forward %s: %.1f ms, differing %zu of %zu\n", size.c_str(), best * 1e3, diff, out.size());
        std::ifstream mb(base + "backward_" + size + ".meta"); mb >> M >> fpm >> H >> W >> inv;
        screen = load<float>(base + "backward_" + size + ".screen"); box = load<int64_t>(base + "backward_" + size + ".box");
        auto pg = load<float>(base + "backward_" + size + ".pg"); ref = load<float>(base + "backward_" + size + ".out");
        out.assign(ref.size(), 0.f); best = 1e9;
        for (int r = 0; r < reps; ++r) {
            auto t = std::chrono::steady_clock::now();
            sdn3d_soft_backward_f32(screen.data(), box.data(), M, fpm, H, W, inv, 1e-10, pg.data(), out.data(), 1);
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
        }
        diff = 0; for (size_t i = 0; i < out.size(); ++i) diff += std::memcmp(&out[i], &ref[i], 4) != 0;
        printf("backward %s: %.1f ms, differing %zu of %zu\n", size.c_str(), best * 1e3, diff, out.size());
    }
}
