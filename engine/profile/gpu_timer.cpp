#include "profile/gpu_timer.hpp"

namespace candela {

GpuTimer::GpuTimer(int frames_in_flight) : frames_(static_cast<size_t>(std::max(frames_in_flight, 1))) {}

bool GpuTimer::collect(Frame& f, bool wait) {
    if (!f.pending) return false;
    if (!wait) {
        for (int i = 0; i < f.used; ++i) {
            GLint ready = 0;
            glGetQueryObjectiv(f.queries[static_cast<size_t>(i)].id(), GL_QUERY_RESULT_AVAILABLE, &ready);
            if (!ready) return false;
        }
    }
    Results r;
    // Every pass of the frame ran between its start and now.
    const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - f.started).count();
    for (int i = 0; i < f.used; ++i) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(f.queries[static_cast<size_t>(i)].id(), GL_QUERY_RESULT, &ns);
        const double ms = static_cast<double>(ns) * 1e-6;
        r.emplace_back(f.names[static_cast<size_t>(i)], ms <= wall_ms + 1.0 ? ms : -1.0);
    }
    latest_ = std::move(r);
    f.pending = false;
    return true;
}

void GpuTimer::begin_frame() {
    // Collect whatever older frames are ready, oldest first, without waiting.
    for (size_t k = 1; k <= frames_.size(); ++k) {
        const size_t i = (static_cast<size_t>(current_ + 1) + k) % frames_.size();
        collect(frames_[i], false);
    }
    current_ = (current_ + 1) % static_cast<int>(frames_.size());
    Frame& f = frames_[static_cast<size_t>(current_)];
    if (f.pending) collect(f, true);  // only when every frame in flight is still busy
    f.used = 0;
    f.names.clear();
    f.pending = true;
    f.started = std::chrono::steady_clock::now();
}

void GpuTimer::begin(const std::string& name) {
    Frame& f = frames_[static_cast<size_t>(current_)];
    if (f.used == static_cast<int>(f.queries.size())) f.queries.push_back(gl::Query::create(GL_TIME_ELAPSED));
    f.names.push_back(name);
    glBeginQuery(GL_TIME_ELAPSED, f.queries[static_cast<size_t>(f.used)].id());
}

void GpuTimer::end() {
    glEndQuery(GL_TIME_ELAPSED);
    ++frames_[static_cast<size_t>(current_)].used;
}

const GpuTimer::Results& GpuTimer::resolve_current() {
    collect(frames_[static_cast<size_t>(current_)], true);
    return latest_;
}

}  // namespace candela
