#pragma once
// What a `render --spp-shard K/N` output is a shard of, written into its .exr header as tags
// (ImageF::tags), and the checks built on them: `candela merge` refuses shards of different
// renders, and `candela farm` skips a shard whose output is already complete (resumable farms).
//
// Tags: candela:shard "K/N" (a merge: the shard indices it holds, "0,1,3/4"), candela:scene (the
// file name as given), candela:scene_hash (FNV-1a 64 of the scene file's bytes: the same scene
// on another machine or path merges, an edited one does not), candela:mode, candela:seed,
// candela:spp (the whole render's, before sharding), candela:size "WxH" and candela:args (every
// other option that changes the image, in a fixed order).
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "image/image.hpp"
#include "options.hpp"

namespace candela::cli {

using Tags = std::map<std::string, std::string>;

// The tags of a --raytrace render with these options (p: render's parsed arguments).
Tags shard_tags(const Parsed& p, const std::string& mode, std::uint32_t seed, int spp, int shard, int shard_count, int width, int height);

// The sample count shard K of N holds per pixel: the samples s < spp with s % N == K.
int shard_samples(int spp, int shard, int shard_count);

// Checks that the images (read from `files`) are shards of one render with disjoint shard
// indices; throws bad_input naming the file and the tag that differs. Images without tags (from
// before tags existed, or not shards) are accepted with a warning. Returns the merged image's
// tags (the union of the shard indices), empty if no image had tags.
Tags check_shards(const std::vector<std::filesystem::path>& files, const std::vector<ImageF>& images);

// Whether `path` is a complete output of the shard tagged `expected`: readable, the same tags,
// every pixel's alpha (sample count) equal to `samples`, and no NaN/Inf. `why` says what is not.
bool shard_complete(const std::filesystem::path& path, const Tags& expected, int samples, std::string& why);

// "K1,K2/N" <-> shard indices and count. parse_shard_tag throws bad_input naming `file`.
std::string shard_tag(const std::vector<int>& shards, int count);
void parse_shard_tag(const std::string& text, const std::string& file, std::vector<int>& shards, int& count);

}  // namespace candela::cli
