// `candela merge OUT.exr SHARD.exr...`: the sample-weighted mean of `render --spp-shard` outputs.
#include "commands.hpp"

#include <filesystem>
#include <vector>

#include "core/error.hpp"
#include "image/image.hpp"
#include "options.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/shard_merge.hpp"
#include "shards.hpp"

namespace candela::cli {

int cmd_merge(const Args& args) {
    const Parsed p = parse(args, {}, {});
    if (p.positional.size() < 2) throw bad_input("merge needs OUT.exr and at least one shard");
    std::vector<ImageF> shards;
    std::vector<std::filesystem::path> files;
    for (size_t i = 1; i < p.positional.size(); ++i) {
        files.emplace_back(p.positional[i]);
        shards.push_back(read_image(files.back()));
    }
    // Shards of another scene, size, seed, mode or sample count, or one given twice, are refused
    // by name (their tags, shards.hpp); the merge is tagged with the shards it holds.
    const Tags tags = check_shards(files, shards);
    ImageF merged = rt::merge_shards(shards);
    merged.tags = tags;
    write_image(p.positional[0], merged);
    return 0;
}

}  // namespace candela::cli
