// `candela merge OUT.exr SHARD.exr...`: the sample-weighted mean of `render --spp-shard` outputs.
#include "commands.hpp"

#include <vector>

#include "core/error.hpp"
#include "image/image.hpp"
#include "options.hpp"
#include "rt/ray_tracer.hpp"

namespace candela::cli {

int cmd_merge(const Args& args) {
    const Parsed p = parse(args, {}, {});
    if (p.positional.size() < 2) throw bad_input("merge needs OUT.exr and at least one shard");
    std::vector<ImageF> shards;
    for (size_t i = 1; i < p.positional.size(); ++i) shards.push_back(read_image(p.positional[i]));
    write_image(p.positional[0], rt::merge_shards(shards));
    return 0;
}

}  // namespace candela::cli
