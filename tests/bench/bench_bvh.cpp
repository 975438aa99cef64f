// BVH build speed and quality: the binned SAH builder at a million triangles, and against the
// full-sweep reference at 100k (the sweep is O(n log^2 n), too slow for more). Counters: SAH cost
// of the tree, its node count and depth, and for the reference runs SAH(binned) / SAH(sweep).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "rt/bvh.hpp"

namespace candela::rt {
namespace {

Aabb triangle_box(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    Aabb t;
    t.extend(a);
    t.extend(b);
    t.extend(c);
    return t;
}

// A UV sphere of `count` triangles with its radius displaced by a few sines: triangles of every
// size and orientation, slivers at the poles, as scanned meshes have.
std::vector<Aabb> displaced_sphere(std::int64_t count) {
    const int stacks = static_cast<int>(std::sqrt(static_cast<double>(count) / 4.0)), slices = 2 * stacks;
    const float pi = 3.14159265f;
    auto point = [&](int i, int j) {
        const float theta = pi * static_cast<float>(i) / static_cast<float>(stacks);
        const float phi = 2.0f * pi * static_cast<float>(j) / static_cast<float>(slices);
        const float r = 1.0f + 0.08f * std::sin(7.0f * theta) * std::cos(5.0f * phi) +
                        0.02f * std::sin(41.0f * theta + 29.0f * phi);
        return r * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    };
    std::vector<Aabb> prims;
    prims.reserve(static_cast<size_t>(2 * stacks * slices));
    for (int i = 0; i < stacks; ++i) {
        for (int j = 0; j < slices; ++j) {
            const glm::vec3 a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
            prims.push_back(triangle_box(a, b, c));
            prims.push_back(triangle_box(a, c, d));
        }
    }
    return prims;
}

// Small triangles scattered uniformly through a unit cube: no coherence at all.
std::vector<Aabb> random_triangles(std::int64_t count) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), offset(-0.01f, 0.01f);
    std::vector<Aabb> prims;
    prims.reserve(static_cast<size_t>(count));
    for (std::int64_t i = 0; i < count; ++i) {
        const glm::vec3 p(unit(rng), unit(rng), unit(rng));
        auto near_p = [&] { return p + glm::vec3(offset(rng), offset(rng), offset(rng)); };
        const glm::vec3 a = near_p(), b = near_p(), c = near_p();
        prims.push_back(triangle_box(a, b, c));
    }
    return prims;
}

void report(benchmark::State& state, const std::vector<Aabb>& prims, const Bvh& bvh) {
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(prims.size()));
    state.counters["sah"] = bvh.stats.sah_cost;
    state.counters["nodes"] = bvh.stats.node_count;
    state.counters["depth"] = bvh.stats.max_depth;
}

template <std::vector<Aabb> (*generate)(std::int64_t)>
void BM_BinnedSah(benchmark::State& state) {
    const std::vector<Aabb> prims = generate(state.range(0));
    Bvh bvh;
    for (auto _ : state) {
        bvh = build_bvh_binned_sah(prims);
        benchmark::DoNotOptimize(bvh.nodes.data());
    }
    report(state, prims, bvh);
}

template <std::vector<Aabb> (*generate)(std::int64_t)>
void BM_SweepSah(benchmark::State& state) {
    const std::vector<Aabb> prims = generate(state.range(0));
    const double binned_sah = build_bvh_binned_sah(prims).stats.sah_cost;
    Bvh bvh;
    for (auto _ : state) {
        bvh = build_bvh_sweep_sah(prims);
        benchmark::DoNotOptimize(bvh.nodes.data());
    }
    report(state, prims, bvh);
    state.counters["sah_binned/sweep"] = binned_sah / bvh.stats.sah_cost;
}

BENCHMARK(BM_BinnedSah<displaced_sphere>)->Arg(1'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BinnedSah<random_triangles>)->Arg(1'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SweepSah<displaced_sphere>)->Arg(100'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SweepSah<random_triangles>)->Arg(100'000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace candela::rt

BENCHMARK_MAIN();
