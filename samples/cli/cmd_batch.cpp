// `candela batch JOBS`: many `render` jobs in one process (start-up and compiles paid once). Each job is a list of
// `render` arguments, parsed and run by the same code as `candela render` (run_render), so a
// job's image equals `candela render` with the same arguments; the jobs share one GL context and
// the programs compiled in it (render_job.hpp). A job that fails (bad input, or an internal
// error) is reported with its index and the jobs file, and the batch goes on with the next.
//
// JOBS is JSON or text. JSON: an array of jobs, or {"args": [common...], "jobs": [...]}, where a
// job is an array of arguments, a string (one command line), or an object of named fields and/or
// "args": {"scene": "a.gltf", "output": "a.png", "size": "320x240", "set": {"ssao.enabled": false}}.
// Text: one job per line (render's arguments; "double quotes" group, '#' starts a comment).
#include "commands.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/command_line.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "gl/handles.hpp"
#include "options.hpp"
#include "render_job.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

namespace batch_detail {  // (named: the command's sources may be compiled as one unity file)

struct Job {
    Args args;
    std::string error;  // set when the job itself is malformed (reported as that job's bad input)
    int line = 0;       // text files: the line
};

// A jobs-file line's arguments (core/command_line.hpp); "render SCENE ..." is accepted too.
Args job_arguments(const std::string& line) {
    Args out = split_command_line(line);
    if (!out.empty() && out[0] == "render") out.erase(out.begin());
    return out;
}

std::string scalar_text(const nlohmann::json& v, const std::string& field) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    if (v.is_number()) return v.dump();
    throw bad_input("\"" + field + "\" must be a string, number or boolean (got " + v.dump() + ")");
}

Args string_array(const nlohmann::json& v, const std::string& field) {
    if (!v.is_array()) throw bad_input("\"" + field + "\" must be an array of strings");
    Args out;
    for (const auto& a : v) out.push_back(scalar_text(a, field));
    return out;
}

// One JSON job as render arguments: the named fields first, then "args" (a later option wins).
Args job_args(const nlohmann::json& j) {
    if (j.is_string()) return job_arguments(j.get<std::string>());
    if (j.is_array()) return string_array(j, "args");
    if (!j.is_object()) throw bad_input("a job must be an object, an array of arguments or a command line (got " + j.dump() + ")");
    // Fields that are one option with one value.
    static const std::vector<std::pair<std::string, std::string>> kOptions = {
        {"output", "-o"},         {"size", "--size"},       {"camera", "--camera"},       {"path", "--path"},
        {"effects", "--effects"}, {"raytrace", "--raytrace"}, {"spp", "--spp"},           {"seed", "--seed"},
        {"max_depth", "--max-depth"}, {"animation", "--animation"}, {"time", "--time"},  {"exposure", "--exposure"},
        {"lighting", "--lighting"}, {"environment", "--environment"}, {"stats", "--stats"}, {"frames", "--frames"},
        {"warmup", "--warmup"},   {"shader_dir", "--shader-dir"}, {"backend", "--backend"}, {"fps", "--fps"}};
    Args out;
    for (const auto& [key, value] : j.items()) {
        if (key == "args") continue;
        if (key == "scene") {
            out.insert(out.begin(), scalar_text(value, key));
        } else if (key == "set") {
            if (value.is_object())
                for (const auto& [knob, v] : value.items()) out.insert(out.end(), {"--set", knob + "=" + scalar_text(v, "set." + knob)});
            else if (value.is_array())
                for (const std::string& knob : string_array(value, key)) out.insert(out.end(), {"--set", knob});
            else out.insert(out.end(), {"--set", scalar_text(value, key)});
        } else if (key == "size" && value.is_array() && value.size() == 2) {
            out.insert(out.end(), {"--size", scalar_text(value[0], key) + "x" + scalar_text(value[1], key)});
        } else {
            const auto it = std::find_if(kOptions.begin(), kOptions.end(), [&](const auto& o) { return o.first == key; });
            if (it == kOptions.end())
                throw bad_input("unknown job field \"" + key +
                                "\" (scene, output, size, camera, path, effects, set, raytrace, spp, seed, max_depth, animation, "
                                "time, fps, exposure, lighting, environment, stats, frames, warmup, shader_dir, backend, args)");
            out.insert(out.end(), {it->second, scalar_text(value, key)});
        }
    }
    if (j.contains("args")) {
        const Args extra = string_array(j.at("args"), "args");
        out.insert(out.end(), extra.begin(), extra.end());
    }
    return out;
}

std::vector<Job> read_jobs(const fs::path& file) {
    std::ifstream in(file);
    if (!fs::is_regular_file(file) || !in) throw bad_input(file.string() + ": no such jobs file");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    const size_t first = text.find_first_not_of(" \t\r\n");
    std::vector<Job> jobs;
    if (first != std::string::npos && (text[first] == '[' || text[first] == '{')) {
        nlohmann::json j;
        try {
            j = nlohmann::json::parse(text);
        } catch (const nlohmann::json::exception& e) {
            throw bad_input(file.string() + ": invalid JSON: " + e.what());
        }
        Args common;
        if (j.is_object()) {
            for (const auto& [key, value] : j.items())
                if (key != "jobs" && key != "args") throw bad_input(file.string() + ": unknown top-level field \"" + key + "\" (jobs, args)");
            if (!j.contains("jobs") || !j.at("jobs").is_array()) throw bad_input(file.string() + ": expected \"jobs\": [...]");
            if (j.contains("args")) {
                try {
                    common = string_array(j.at("args"), "args");
                } catch (const Error& e) {
                    throw bad_input(file.string() + ": " + e.what());
                }
            }
            j = j.at("jobs");
        }
        for (const auto& entry : j) {
            Job job;
            try {
                job.args = common;
                const Args own = job_args(entry);
                job.args.insert(job.args.end(), own.begin(), own.end());
            } catch (const Error& e) {
                job.error = e.what();
            }
            jobs.push_back(std::move(job));
        }
    } else {
        std::istringstream lines(text);
        std::string line;
        for (int n = 1; std::getline(lines, line); ++n) {
            Job job;
            job.line = n;
            try {
                job.args = job_arguments(line);
                if (job.args.empty()) continue;
            } catch (const Error& e) {
                job.error = e.what();
            }
            jobs.push_back(std::move(job));
        }
    }
    if (jobs.empty()) throw bad_input(file.string() + ": no jobs");
    return jobs;
}

// The value of `name` in args (last occurrence, "--name V" or "--name=V"), or "".
std::string find_option(const Args& args, const std::string& name) {
    std::string v;
    for (size_t i = 0; i < args.size(); ++i) {
        if (args[i] == name && i + 1 < args.size()) v = args[i + 1];
        else if (args[i].rfind(name + "=", 0) == 0) v = args[i].substr(name.size() + 1);
    }
    return v;
}

struct GlCounts {
    int textures, buffers, framebuffers, vertex_arrays, queries, samplers;
    bool operator==(const GlCounts&) const = default;
    std::string text() const {
        return "textures " + std::to_string(textures) + ", buffers " + std::to_string(buffers) + ", framebuffers " +
               std::to_string(framebuffers) + ", vertex arrays " + std::to_string(vertex_arrays) + ", queries " +
               std::to_string(queries) + ", samplers " + std::to_string(samplers);
    }
};
GlCounts live_gl_objects() {
    return {gl::Texture::live(), gl::Buffer::live(), gl::Framebuffer::live(), gl::VertexArray::live(), gl::Query::live(), gl::Sampler::live()};
}

double rss_mib() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    statm >> pages >> resident;
    return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

}  // namespace batch_detail

int cmd_batch(const Args& args) {
    using namespace batch_detail;
    const Parsed p = parse(args, {"--backend"}, {"--debug-gl", "--quiet", "--timings", "--no-share-programs"});
    if (p.positional.size() != 1) throw bad_input("batch needs exactly one JOBS file (got " + std::to_string(p.positional.size()) + ")");
    const fs::path file = p.positional[0];
    if (p.flags.count("--quiet")) log::set_level(log::Level::warn);
    const std::vector<Job> jobs = read_jobs(file);

    // One context for the batch: --backend, else the first job's --backend, else auto.
    Backend backend = backend_option(p, true);
    bool debug = p.flags.count("--debug-gl") > 0;
    if (const char* env = std::getenv("CANDELA_DEBUG_GL"); env && std::string(env) == "1") debug = true;
    for (const Job& job : jobs) {
        if (!p.has("--backend") && backend == Backend::auto_select) {
            const auto b = parse_backend(find_option(job.args, "--backend"));
            if (b && *b != Backend::glfw) backend = *b;
        }
        for (const std::string& a : job.args) debug = debug || a == "--debug-gl";
    }
    ContextOptions ctx_options;
    ctx_options.debug = debug;
    ContextResult ctx = create_context(backend, ctx_options);
    if (!ctx.context) {
        std::fprintf(stderr, "candela: error: no usable OpenGL: %s\n", ctx.error.c_str());
        return static_cast<int>(ExitCode::no_gl);
    }
    if (!ctx.notice.empty()) log::warn(ctx.notice);
    log::info(std::string("batch: backend ") + to_string(ctx.context->backend()) + ": " + ctx.context->device_string() + "; " +
              std::to_string(jobs.size()) + " job(s) from " + file.string());

    BatchSession session;
    session.context = ctx.context.get();
    session.debug = debug;
    session.share_programs = p.flags.count("--no-share-programs") == 0;
    const GlCounts start_counts = live_gl_objects();
    const double rss_start = rss_mib();
    const auto t_batch = std::chrono::steady_clock::now();
    std::vector<std::pair<size_t, int>> failed;  // job index (1-based), exit code
    bool grew = false;
    const log::Level level = log::level();
    for (size_t i = 0; i < jobs.size(); ++i) {
        const Job& job = jobs[i];
        const std::string where = file.string() + (job.line ? ":" + std::to_string(job.line) : "") + ": job " + std::to_string(i + 1);
        const auto t0 = std::chrono::steady_clock::now();
        int rc = 0;
        if (!job.error.empty()) {
            std::fprintf(stderr, "candela: %s: error: %s\n", where.c_str(), job.error.c_str());
            rc = static_cast<int>(ExitCode::bad_input);
        } else {
            try {
                rc = run_render(job.args, &session);
            } catch (const Error& e) {
                std::fprintf(stderr, "candela: %s: error: %s\n", where.c_str(), e.what());
                rc = static_cast<int>(e.code());
            } catch (const std::exception& e) {
                std::fprintf(stderr, "candela: %s: internal error: %s\n", where.c_str(), e.what());
                rc = static_cast<int>(ExitCode::internal);
            }
        }
        log::set_level(level);  // a job's --quiet is its own
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        // Everything a job made on the GPU is freed with it (programs excepted: they are shared).
        const GlCounts counts = live_gl_objects();
        if (!(counts == start_counts)) {
            log::warn(where + ": GL objects left after the job: " + counts.text() + " (before the batch: " + start_counts.text() + ")");
            grew = true;
        }
        if (rc != 0) {
            failed.emplace_back(i + 1, rc);
            std::fprintf(stderr, "candela: %s: failed (exit %d)\n", where.c_str(), rc);
        }
        const std::string out = find_option(job.args, "-o").empty() ? find_option(job.args, "--output") : find_option(job.args, "-o");
        if (p.flags.count("--timings"))
            std::fprintf(stderr, "candela: batch job %zu/%zu %s: %.1f ms%s%s; RSS %.1f MiB\n", i + 1, jobs.size(), rc ? "failed" : "ok", ms,
                         out.empty() ? "" : ", ", out.c_str(), rss_mib());
    }
    const double total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_batch).count();
    std::string failed_text;
    // Exit 1 if a job failed internally (a bug, a GL error), else the first failed job's code (2:
    // bad input), else 0.
    int code = 0;
    for (const auto& [index, rc] : failed) {
        failed_text += (failed_text.empty() ? ": job " : ", ") + std::to_string(index) + " (exit " + std::to_string(rc) + ")";
        if (code == 0 || rc == static_cast<int>(ExitCode::internal)) code = rc;
    }
    std::fprintf(stderr, "candela: batch: %zu job(s), %zu ok, %zu failed%s; %.2f s, %.3f s per job; GL objects %s; RSS %.1f -> %.1f MiB\n",
                 jobs.size(), jobs.size() - failed.size(), failed.size(), failed_text.c_str(), total_ms / 1000.0,
                 total_ms / 1000.0 / static_cast<double>(jobs.size()), grew ? "LEFT BEHIND (see above)" : "all freed after every job",
                 rss_start, rss_mib());
    return code;
}

}  // namespace candela::cli
