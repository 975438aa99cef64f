#pragma once
// Deferred lighting with a multisampled G-buffer (FrameSampling::samples > 1): how many pixels
// the last lighting pass shaded more than once (once per surface its samples show). Counted only
// with CANDELA_AA_STATS=1 in the environment (a readback that waits for the dispatch; the name
// is the anti-aliasing documentation's); the renderer never reads it.

namespace candela {

struct DeferredEdgeStats {
    long long edge_pixels = 0;      // pixels shaded more than once (samples on two or more surfaces)
    long long geometry_pixels = 0;  // pixels with geometry in at least one sample
    long long shadings = 0;         // shadings in all (one per surface a pixel's samples show)
    int samples = 0;                // the G-buffer's samples per pixel (0: no count yet)
};
// The last counted lighting pass's (any renderer in this process).
DeferredEdgeStats last_deferred_edge_stats();

}  // namespace candela
