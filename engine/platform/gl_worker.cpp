#include "platform/gl_worker.hpp"

#include <glad/gl.h>

#include <cstdio>

#include "core/error.hpp"
#include "platform/context.hpp"

namespace candela {

struct GlWorker::Job {
    std::function<void()> work;
    GLsync after = nullptr;  // the submitting context's commands before the job
    std::mutex mutex;
    std::condition_variable cv;
    bool done = false;
    std::exception_ptr error;
};

GlWorker::GlWorker(std::unique_ptr<SharedContext> context) : context_(std::move(context)) {
    if (!context_) return;
    // The thread makes the context current and says whether that worked before anything is queued.
    std::unique_lock<std::mutex> lock(mutex_);
    bool started = false;
    thread_ = std::thread([this, &started] {
        const bool ok = context_->make_current();
        {
            std::lock_guard<std::mutex> l(mutex_);
            running_ = ok;
            started = true;
        }
        cv_.notify_all();
        if (ok) loop();
    });
    cv_.wait(lock, [&] { return started; });
    if (!running_) {
        lock.unlock();
        thread_.join();
    }
}

GlWorker::~GlWorker() {
    if (thread_.joinable()) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }
}

void GlWorker::loop() {
    for (;;) {
        Ticket job;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (queue_.empty()) break;  // stop_ and nothing left
            job = std::move(queue_.front());
            queue_.pop_front();
        }
        try {
            // The submitter flushed after fencing, so the fence signals without our flush.
            glClientWaitSync(job->after, 0, GL_TIMEOUT_IGNORED);
            glDeleteSync(job->after);
            job->work();
            glFinish();
            // The worker's context has no debug callback: its errors are reported here, and so
            // by wait() on the main thread.
            if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
                char text[96];
                std::snprintf(text, sizeof text, "GL error 0x%04x in a job on the GL worker context", static_cast<unsigned>(e));
                while (glGetError() != GL_NO_ERROR) {}
                throw Error(ExitCode::internal, text);
            }
        } catch (...) {
            job->error = std::current_exception();
        }
        {
            std::lock_guard<std::mutex> lock(job->mutex);
            job->done = true;
        }
        job->cv.notify_all();
    }
    context_->release();
}

GlWorker::Ticket GlWorker::submit(std::function<void()> work) {
    auto job = std::make_shared<Job>();
    if (!running_) {
        try {
            work();
        } catch (...) {
            job->error = std::current_exception();
        }
        job->done = true;
        return job;
    }
    job->work = std::move(work);
    job->after = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        queue_.push_back(job);
    }
    cv_.notify_all();
    return job;
}

void GlWorker::wait(const Ticket& ticket) {
    if (!ticket) return;
    std::unique_lock<std::mutex> lock(ticket->mutex);
    ticket->cv.wait(lock, [&] { return ticket->done; });
    if (ticket->error) std::rethrow_exception(ticket->error);
}

}  // namespace candela
