#include "rt/shard_merge.hpp"

#include "core/error.hpp"

namespace candela::rt {

ImageF merge_shards(const std::vector<ImageF>& shards) {
    if (shards.empty()) throw bad_input("merge needs at least one shard");
    ImageF out(shards[0].width, shards[0].height, 4);
    for (const ImageF& s : shards)
        if (s.width != out.width || s.height != out.height || s.channels != 4)
            throw bad_input("merge: shards differ in size or have no sample-count channel");
    for (size_t i = 0; i < static_cast<size_t>(out.width) * out.height; ++i) {
        double sum[3] = {0, 0, 0}, count = 0;
        for (const ImageF& s : shards) {
            const float* p = s.pixels.data() + i * 4;
            for (int c = 0; c < 3; ++c) sum[c] += static_cast<double>(p[c]) * p[3];
            count += p[3];
        }
        float* o = out.pixels.data() + i * 4;
        for (int c = 0; c < 3; ++c) o[c] = count > 0 ? static_cast<float>(sum[c] / count) : 0.0f;
        o[3] = static_cast<float>(count);
    }
    return out;
}

}  // namespace candela::rt
