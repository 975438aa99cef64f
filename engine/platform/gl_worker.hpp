#pragma once
// A second OpenGL context on its own thread, sharing the main context's objects, for GL work
// that can run beside the main thread's: today material textures' mipmaps (gl::draw_mipmaps),
// drawn while the main thread builds Candela's programs and lights the environment. The second
// core does it.
//
// GL's rules for objects shared between contexts (4.5 core, appendix D.3) are
// kept: a fence after the main context's upload that the worker waits for before it starts,
// glFinish in the worker before the job counts as done, and the main context binds the object
// again after it has waited (every draw binds its textures).
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

namespace candela {

class SharedContext;

class GlWorker {
public:
    // Takes a context that shares objects with the one current on the calling thread.
    explicit GlWorker(std::unique_ptr<SharedContext> context);
    ~GlWorker();  // finishes the queued jobs, then stops the thread
    GlWorker(const GlWorker&) = delete;
    GlWorker& operator=(const GlWorker&) = delete;

    struct Job;
    using Ticket = std::shared_ptr<Job>;
    // Call with the main context current: fences the commands issued so far, then queues `work`
    // to run in the worker's context after them.
    Ticket submit(std::function<void()> work);
    // Blocks until the job ran (and its GL commands completed); rethrows what it threw.
    // A null ticket is done.
    static void wait(const Ticket& ticket);
    // Whether the worker's context became current on its thread; false: jobs run nowhere and
    // submit() runs them on the calling thread instead.
    bool running() const { return running_; }

private:
    void loop();
    std::unique_ptr<SharedContext> context_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Ticket> queue_;
    bool stop_ = false;
    bool running_ = false;
    std::thread thread_;
};

}  // namespace candela
