#include "rt/progress_bar.hpp"

#include <cstdio>

namespace candela::rt {

void progress_bar(int done, int total, double elapsed_s) {
    const int width = 30;
    const int filled = total > 0 ? done * width / total : width;
    const double eta = done > 0 ? elapsed_s / done * (total - done) : 0.0;
    std::fprintf(stderr, "\r[%.*s%.*s] %3d%% %d/%d spp, %.1f s, ETA %.1f s ", filled,
                 "##############################", width - filled, "                              ",
                 total ? done * 100 / total : 100, done, total, elapsed_s, eta);
    if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace candela::rt
