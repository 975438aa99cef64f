#pragma once
// An effect's accuracy sweep as data: which scene, which raster output against which tracer
// mode, which knob settings to vary, and which of them the engine ships. The accuracy engine
// (engine/accuracy/) runs every registered effect's sweeps; it knows no effect by name.
//
// The type lives here, beside the Effect interface that returns it, and not in engine/accuracy:
// effects declare their sweeps as data and include only this header, the accuracy engine
// includes the effects (their registry). The dependency goes one way, accuracy -> effects.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rt/ray_tracer.hpp"

namespace candela {

struct Features;

struct AccuracySweep {
    // What the raster variant outputs and is compared: the radiance, or a debug buffer
    // (debug.view=visibility of light 0, ao, indirect).
    enum class Buffer { radiance, visibility, ao, indirect };

    struct Variant {
        std::string name;
        std::string effects;             // --effects
        std::vector<std::string> knobs;  // --set KNOB=VALUE
    };

    struct Reference {
        rt::Mode mode = rt::Mode::direct;
        int spp = 16;
        int max_depth = -1;             // -1: the tracer's default
        // 0: pixel centres, as the rasterizer samples them, so that the measured error is the
        // effect's and not the rasterizer's own edge aliasing; 1 (or -1, the tracer's default):
        // the box-filtered pixel average.
        int jitter = 0;
        bool indirect_occlusion = true;
    };

    // Which pixels the error is measured on: all, or the edge pixels (anti-aliasing): those whose
    // 3x3 neighbourhood in the reference spans more than a tenth of the reference's largest
    // luminance (silhouettes, texture and shading edges; flat parts excluded).
    enum class Region { all, edges };

    std::string effect;                      // the report's section ("shadows", "shadows_colour", ...)
    Region region = Region::all;
    std::string scene;                       // sample scene file name (or generated:...)
    Buffer buffer = Buffer::radiance;
    std::vector<std::string> own_passes;     // the passes whose time is the effect's; empty: the frame
    std::optional<Reference> reference;      // none: time only
    std::optional<Reference> split;          // a second reference (RSM: without occlusion)
    std::vector<Variant> variants;
    std::string shipped;                     // the variant with the engine's defaults
    std::string compared;                    // what is compared with what, for the report
    std::string reading;                     // what the error is made of
    std::function<bool(const Features&)> needed;  // the scene calls for the effect
};

}  // namespace candela
