#pragma once
// GPU time per pass with GL_TIME_ELAPSED queries, double-buffered across frames so that reading
// results never stalls the pipeline in a frame loop; stills ask for the current frame at once.
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "gl/handles.hpp"

namespace candela {

class GpuTimer {
public:
    explicit GpuTimer(int frames_in_flight = 3);

    void begin_frame();
    void begin(const std::string& name);  // not nestable (GL_TIME_ELAPSED)
    void end();

    // Pass name, ms; -1 where the driver's answer cannot be right: longer than the wall-clock
    // time from the frame's start to its collection (llvmpipe can answer with its absolute
    // clock, hours: see Renderer::render).
    using Results = std::vector<std::pair<std::string, double>>;
    // Results of the newest frame whose queries are ready without waiting (may be empty).
    const Results& latest() const { return latest_; }
    // Waits for the current frame's queries (after glFinish they are ready) and returns them.
    const Results& resolve_current();

private:
    struct Frame {
        std::vector<gl::Query> queries;
        std::vector<std::string> names;
        int used = 0;
        bool pending = false;
        std::chrono::steady_clock::time_point started;
    };
    bool collect(Frame& frame, bool wait);
    std::vector<Frame> frames_;
    int current_ = -1;
    Results latest_;
};

}  // namespace candela
