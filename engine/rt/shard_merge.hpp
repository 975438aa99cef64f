#pragma once
// Merging the images of --spp-shard runs (`candela merge`, the render farm).
#include <vector>

#include "image/image.hpp"

namespace candela::rt {

// Merges shard images (alpha = sample count) into one: the sample-weighted mean.
ImageF merge_shards(const std::vector<ImageF>& shards);

}  // namespace candela::rt
