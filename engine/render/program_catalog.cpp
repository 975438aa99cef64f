#include "render/program_catalog.hpp"

#include <algorithm>
#include <map>
#include <mutex>

#include "core/error.hpp"
#include "render/effect_registry.hpp"

namespace candela {

const std::vector<ProgramDesc>& raster_programs() {
    using S = ShaderStage;
    // The base programs (render/), then every registered effect's (effects/<name>/).
    static const std::vector<ProgramDesc> all = [] {
    std::vector<ProgramDesc> v = {
        {"forward", {{S::vertex, "forward/forward.vert"}, {S::fragment, "forward/forward.frag"}}, {}},
        {"sky", {{S::vertex, "forward/sky.vert"}, {S::fragment, "forward/sky.frag"}}, {}},
        {"tonemap", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "post/tonemap.frag"}}, {}},
        {"copy", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "post/copy.frag"}}, {}},
        {"gbuffer", {{S::vertex, "forward/forward.vert"}, {S::fragment, "deferred/gbuffer.frag"}}, {}},
        {"deferred_light", {{S::compute, "deferred/light.comp"}}, {}},
        {"deferred_light_ms", {{S::compute, "deferred/light.comp"}}, {"MULTISAMPLED"}},
        {"deferred_light_ms_edges", {{S::compute, "deferred/light.comp"}}, {"MULTISAMPLED", "EDGE_GROUPS"}},
        {"gbuffer_resolve", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "deferred/gbuffer_resolve.frag"}}, {}},
        {"depth_normals", {{S::vertex, "forward/forward.vert"}, {S::fragment, "forward/normals.frag"}}, {}},
        {"depth_prepass", {{S::vertex, "forward/forward.vert"}, {S::fragment, "forward/depth.frag"}}, {"DEPTH_ONLY"}},
        {"depth_prepass_mask", {{S::vertex, "forward/forward.vert"}, {S::fragment, "forward/depth.frag"}}, {}},
        {"debug_view", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "post/debug_view.frag"}}, {}},
        {"brdf_lut", {{S::compute, "env/brdf_lut.comp"}}, {}},
        {"equirect_to_cube", {{S::compute, "env/equirect_to_cube.comp"}}, {}},
        {"prefilter", {{S::compute, "env/prefilter.comp"}}, {}},
        {"light_tiles", {{S::compute, "forward/light_tiles.comp"}}, {}},
        {"mip_downsample", {{S::vertex, "post/mip_downsample.vert"}, {S::fragment, "post/mip_downsample.frag"}}, {}},
        {"mip_halve_2d", {{S::compute, "env/mip_halve.comp"}}, {}},
        {"mip_halve_cube_array", {{S::compute, "env/mip_halve.comp"}}, {"CUBE_ARRAY"}},
    };
    for (const Effect* e : effect_registry())
        for (ProgramDesc& d : e->programs()) v.push_back(std::move(d));
    return v;
    }();
    return all;
}

const ProgramDesc& program_desc(const std::string& name) {
    for (const ProgramDesc& d : raster_programs())
        if (d.name == name) return d;
    // "BASE#DEFINE,DEFINE VALUE,...": BASE built with more defines (a specialised variant, such as
    // the forward program without the features a frame does not use: render/passes/pass_env.hpp).
    if (const size_t hash = name.find('#'); hash != std::string::npos) {
        static std::mutex mutex;
        static std::map<std::string, ProgramDesc> variants;  // node-based: references stay valid
        const std::lock_guard<std::mutex> lock(mutex);
        if (auto it = variants.find(name); it != variants.end()) return it->second;
        ProgramDesc d = program_desc(name.substr(0, hash));
        d.name = name;
        for (size_t i = hash + 1; i < name.size();) {
            const size_t end = std::min(name.find(',', i), name.size());
            if (end > i) d.defines.push_back(name.substr(i, end - i));
            i = end + 1;
        }
        return variants.emplace(name, std::move(d)).first->second;
    }
    throw Error(ExitCode::internal, "no shader program named '" + name + "'");
}

std::vector<ProgramDesc> ray_tracer_variants() {
    // One program per tracer mode (rt::mode_program: direct shares path's), each without and
    // with every feature define, and as compiled for a scene without textures or spheres
    // (RT_NO_TEXTURES, RT_NO_SPHERES: ray_tracer.cpp compiles that code out when unused).
    struct ModeFile {
        const char* name;
        const char* file;
    };
    static const ModeFile modes[] = {{"MODE_AO", "rt/modes/ao.comp"},
                                     {"MODE_PRIMARY", "rt/modes/primary.comp"},
                                     {"MODE_PATH", "rt/modes/path.comp"},
                                     {"MODE_INDIRECT", "rt/modes/indirect.comp"},
                                     {"MODE_WHITTED", "rt/modes/whitted.comp"},
                                     {"MODE_VISIBILITY", "rt/modes/visibility.comp"},
                                     {"MODE_BOUNCE", "rt/modes/bounce.comp"},
                                     {"MODE_HITS", "rt/modes/hits.comp"}};
    std::vector<ProgramDesc> out;
    for (const ModeFile& mode : modes)
        for (int variant : {0, 1, 2}) {
            const bool features = variant == 1;
            std::vector<std::string> defines;
            if (features)
                for (const char* f : {"HAS_EMITTERS", "HAS_TRANSMISSION", "HAS_BLEND", "HAS_MASK", "RT_STATS"}) defines.push_back(f);
            if (variant == 2)
                for (const char* f : {"HAS_EMITTERS", "RT_NO_TEXTURES", "RT_NO_SPHERES"}) defines.push_back(f);
            if (features && std::string(mode.name) == "MODE_PATH") defines.push_back("HAS_ENV_MAP_SAMPLING");  // path/direct only
            std::string name = std::string("trace ") + mode.name;
            for (const auto& d : defines) name += " " + d;
            out.push_back({name, {{ShaderStage::compute, mode.file}}, defines});
        }
    return out;
}

}  // namespace candela
