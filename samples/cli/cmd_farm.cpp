// `candela farm`: the tracer's work that outgrows one machine (converged references, accuracy
// sweeps) as independent tasks for a batch scheduler. Candela does not schedule: it
// writes a farm directory that Slurm (sbatch array + a dependent finishing job), GNU parallel,
// Kubernetes indexed jobs or HTCondor run, one command line per task index.
//
//   candela farm reference SCENE -o DIR --shards N [render's options]   N shards of one render
//   candela farm sweep [SCENE...] -o DIR [bench accuracy's options]     one task per sweep section
//     both: [--sbatch ARG]... (#SBATCH lines) [--dry-run] (print, write nothing) [--submit [--wait]]
//   candela farm task DIR INDEX     runs task INDEX; skips it if its output is complete (idempotent)
//   candela farm finish DIR         merges the shards / assembles the sweep; a failed task is
//                                   reported with its log (exit 1)
//   candela farm status DIR         each task: done, or why not, and its log
//   candela farm submit DIR [--wait]  (re)submits DIR's Slurm jobs: complete tasks skip
//
// DIR holds farm.json (the job), tasks.txt (task i's command on line i + 1), run-task.sh INDEX,
// slurm/array.sbatch, slurm/finish.sbatch, submit-slurm.sh, logs/ and the outputs. Paths in it
// are absolute: every node must see DIR, the scene and the candela binary at the same paths (a
// shared file system, as clusters have).
#include "commands.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <climits>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "accuracy.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "image/batch_stats.hpp"
#include "image/image.hpp"
#include "image/image_io.hpp"
#include "options.hpp"
#include "render_job.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/shard_merge.hpp"
#include "shards.hpp"

extern char** environ;

namespace candela::cli {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr int kFarmVersion = 1;

// render's options that a reference passes on to every shard (what render accepts, without
// where the output goes and the shard itself, which the farm sets).
std::vector<std::string> reference_value_options() {
    std::vector<std::string> v = kSceneSetupOptions;
    v.insert(v.end(), {"--raytrace", "--spp", "--max-depth", "--seed", "--exposure"});
    return v;
}

fs::path self_exe() {
    char buf[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) throw Error(ExitCode::internal, "farm: cannot find the candela executable (/proc/self/exe)");
    buf[n] = '\0';
    return buf;
}

// Single quotes for sh: the farm's paths may hold spaces.
std::string sh_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string read_text(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

void write_file(const fs::path& path, const std::string& text, bool executable = false) {
    const fs::path tmp = path.string() + ".tmp";
    {
        std::ofstream out(tmp);
        out << text;
        if (!out) throw bad_input(path.string() + ": cannot write");
    }
    fs::rename(tmp, path);
    if (executable) fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add);
}

// The last `n` lines of a log, indented (what a failed task said).
std::string log_tail(const fs::path& log, int n) {
    if (!fs::exists(log)) return "    (no log: the task has not run)\n";
    std::vector<std::string> lines;
    std::ifstream in(log);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    std::string out;
    for (size_t i = lines.size() > static_cast<size_t>(n) ? lines.size() - static_cast<size_t>(n) : 0; i < lines.size(); ++i)
        out += "    | " + lines[i] + "\n";
    return out.empty() ? "    (the log is empty)\n" : out;
}

struct Farm {
    fs::path dir;
    json spec;  // farm.json
    int tasks() const { return spec.at("tasks").get<int>(); }
    std::string kind() const { return spec.at("kind").get<std::string>(); }
    fs::path log(int i) const { return dir / "logs" / ("task_" + std::to_string(i) + ".log"); }
    fs::path shard(int i) const {
        char name[32];
        std::snprintf(name, sizeof name, "shard_%04d.exr", i);
        return dir / "shards" / name;
    }
    fs::path section(int i) const { return dir / "sections" / std::to_string(i); }
};

Farm load_farm(const std::string& dir_arg) {
    Farm f;
    f.dir = fs::absolute(dir_arg).lexically_normal();
    const fs::path file = f.dir / "farm.json";
    if (!fs::is_regular_file(file)) throw bad_input(dir_arg + ": not a farm directory (no farm.json; 'candela farm reference|sweep ... -o DIR' writes one)");
    try {
        f.spec = json::parse(read_text(file));
        if (f.spec.at("candela_farm").get<int>() != kFarmVersion) throw bad_input(file.string() + ": farm format version is not " + std::to_string(kFarmVersion));
        const std::string kind = f.kind();
        if ((kind != "reference" && kind != "sweep") || f.tasks() < 1) throw bad_input(file.string() + ": kind must be reference or sweep, with tasks >= 1");
    } catch (const json::exception& e) {
        throw bad_input(file.string() + ": " + e.what());
    }
    return f;
}

// The arguments a farm passes on to its tasks: `args` without the farm's own options (`drop`,
// with their values, and `drop_flags`); positional arguments and the values of `paths` options
// that name existing files become absolute, since the tasks run elsewhere.
Args pass_on(const Args& args, const std::vector<std::string>& with_value, const std::vector<std::string>& drop,
             const std::vector<std::string>& drop_flags, const std::vector<std::string>& paths, Args* positional) {
    const auto in = [](const std::vector<std::string>& v, const std::string& x) { return std::find(v.begin(), v.end(), x) != v.end(); };
    const auto absolute = [](const std::string& a) { return fs::exists(a) ? fs::absolute(a).lexically_normal().string() : a; };
    Args out;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a.size() < 2 || a[0] != '-') {
            (positional ? *positional : out).push_back(absolute(a));
            continue;
        }
        const size_t eq = a.rfind("--", 0) == 0 ? a.find('=') : std::string::npos;
        const std::string name = a.substr(0, eq);
        const bool takes_value = in(with_value, name) && eq == std::string::npos && i + 1 < args.size();
        if (in(drop, name) || in(drop_flags, name)) {
            if (takes_value) ++i;
            continue;
        }
        if (eq != std::string::npos && in(paths, name)) {
            out.push_back(name + "=" + absolute(a.substr(eq + 1)));
            continue;
        }
        out.push_back(a);
        if (takes_value) out.push_back(in(paths, name) ? absolute(args[++i]) : args[++i]);
    }
    return out;
}

// --- reference --------------------------------------------------------------------------

struct ShardJob {
    Args args;        // render's arguments for shard i (without -o)
    Tags tags;        // what its output must carry
    int samples = 0;  // per pixel
};

ShardJob shard_job(const Farm& f, int i) {
    ShardJob j;
    j.args = {f.spec.at("scene").get<std::string>()};
    for (const auto& a : f.spec.at("render_args")) j.args.push_back(a.get<std::string>());
    const int n = f.tasks();
    j.args.insert(j.args.end(), {"--spp-shard", std::to_string(i) + "/" + std::to_string(n)});
    // The same parse and defaults as render's (cmd_render.cpp): spp 16, seed 1, 512x512, path.
    const Parsed p = parse(j.args, [] { auto v = reference_value_options(); v.push_back("--spp-shard"); return v; }(), kSceneSetupFlags);
    const int spp = p.has("--spp") ? parse_int("--spp", p.get("--spp"), 1, 1 << 24) : 16;
    const auto seed = static_cast<std::uint32_t>(p.has("--seed") ? parse_int("--seed", p.get("--seed"), 0, 2147483647) : 1);
    int w = 512, h = 512;
    if (p.has("--size")) parse_size(p.get("--size"), w, h);
    j.tags = shard_tags(p, p.has("--raytrace") ? p.get("--raytrace") : "path", seed, spp, i, n, w, h);
    j.samples = shard_samples(spp, i, n);
    return j;
}

json reference_spec(const Parsed& p, const Args& args) {
    if (p.positional.size() != 1) throw bad_input("farm reference needs exactly one SCENE (got " + std::to_string(p.positional.size()) + ")");
    if (!p.has("--shards")) throw bad_input("farm reference needs --shards N (the number of array tasks)");
    const int shards = parse_int("--shards", p.get("--shards"), 1, 100000);
    const int spp = p.has("--spp") ? parse_int("--spp", p.get("--spp"), 1, 1 << 24) : 16;
    if (shards > spp) throw bad_input("--shards " + std::to_string(shards) + " is more than --spp " + std::to_string(spp) + ": a shard would hold no samples");
    const std::string mode = p.has("--raytrace") ? p.get("--raytrace") : "path";
    if (!rt::parse_mode(mode)) throw bad_input("--raytrace '" + mode + "' must be whitted, path, direct, indirect, ao, primary or visibility");
    std::string scene = p.positional.front();
    if (scene.rfind("generated:", 0) != 0) {
        if (!fs::is_regular_file(scene)) throw bad_input(scene + ": no such file");
        scene = fs::absolute(scene).lexically_normal().string();
    }
    if (!image_io_built()) throw bad_input("farm reference writes .exr shards, which needs OpenImageIO: this candela was built without it");
    // render's own arguments, in their order, with --raytrace made explicit; the farm's removed.
    std::vector<std::string> with_value = reference_value_options();
    with_value.insert(with_value.end(), {"-o", "--shards", "--sbatch"});
    Args positional;
    Args render_args = pass_on(args, with_value, {"-o", "--shards", "--sbatch"}, {"--dry-run", "--submit", "--wait", "--batch-stats"},
                               {"--environment", "--shader-dir"}, &positional);
    if (!p.has("--raytrace")) render_args.insert(render_args.begin(), {"--raytrace", mode});
    json s;
    s["kind"] = "reference";
    s["tasks"] = shards;
    s["scene"] = scene;
    s["render_args"] = render_args;
    s["batch_stats"] = p.flags.count("--batch-stats") > 0;
    return s;
}

int task_reference(const Farm& f, int i) {
    const ShardJob j = shard_job(f, i);
    const fs::path out = f.shard(i);
    std::string why;
    if (shard_complete(out, j.tags, j.samples, why)) {
        std::printf("task %d: %s is complete (%d samples per pixel): skipped\n", i, out.string().c_str(), j.samples);
        return 0;
    }
    if (fs::exists(out)) std::printf("task %d: %s is not complete (%s): rendering it again\n", i, out.string().c_str(), why.c_str());
    fs::create_directories(out.parent_path());
    // Written under another name and renamed when whole: a task killed mid-write leaves no file
    // that looks like a shard.
    const fs::path partial = out.parent_path() / (".partial_" + out.filename().string());
    Args args = j.args;
    args.insert(args.end(), {"-o", partial.string()});
    const int rc = run_render(args, nullptr);
    if (rc != 0) return rc;
    fs::rename(partial, out);
    if (!shard_complete(out, j.tags, j.samples, why))
        throw Error(ExitCode::internal, out.string() + ": the render finished but its output is not a complete shard (" + why + ")");
    std::printf("task %d: wrote %s (%d samples per pixel)\n", i, out.string().c_str(), j.samples);
    return 0;
}

// Which tasks are not done, with why; empty when all are.
std::vector<std::pair<int, std::string>> missing_tasks(const Farm& f) {
    std::vector<std::pair<int, std::string>> missing;
    for (int i = 0; i < f.tasks(); ++i) {
        std::string why;
        if (f.kind() == "reference") {
            const ShardJob j = shard_job(f, i);
            if (!shard_complete(f.shard(i), j.tags, j.samples, why)) missing.emplace_back(i, f.shard(i).string() + ": " + why);
        } else if (!fs::is_regular_file(f.section(i) / "section.json")) {
            missing.emplace_back(i, (f.section(i) / "section.json").string() + ": no output yet");
        }
    }
    return missing;
}

int finish_reference(const Farm& f) {
    std::vector<fs::path> files;
    std::vector<ImageF> shards;
    for (int i = 0; i < f.tasks(); ++i) {
        files.push_back(f.shard(i));
        shards.push_back(read_image(files.back()));
    }
    ImageF merged = rt::merge_shards(shards);
    merged.tags = check_shards(files, shards);
    if (const std::size_t bad = count_nonfinite(merged)) throw Error(ExitCode::internal, "farm: the merged reference has " + std::to_string(bad) + " non-finite values");
    const fs::path out = f.dir / "reference.exr";
    write_image(out, merged);
    std::printf("farm: merged %d shards into %s (%g samples per pixel)\n", f.tasks(), out.string().c_str(), static_cast<double>(merged.pixels[3]));
    // The per-pixel standard error of the mean from the spread of the shards, each an independent
    // batch (docs/raytracing.md): a reference with its error bars, for `compare --batches
    // --against reference.exr --ref-stderr reference_stderr.exr`.
    if (f.spec.value("batch_stats", false)) {
        if (f.tasks() < 2) throw bad_input("farm: --batch-stats needs at least 2 shards");
        ImageF mean, se;
        batch_mean_and_stderr(shards, mean, se);
        write_image(f.dir / "reference_stderr.exr", se);
        double sum = 0;
        for (size_t k = 0; k < se.pixels.size(); k += static_cast<size_t>(se.channels)) sum += (se.pixels[k] + se.pixels[k + 1] + se.pixels[k + 2]) / 3.0;
        std::printf("farm: wrote %s (mean standard error %.4g per pixel and channel)\n", (f.dir / "reference_stderr.exr").string().c_str(),
                    sum / (static_cast<double>(se.width) * se.height));
    }
    return 0;
}

// --- sweep --------------------------------------------------------------------------------

// bench accuracy's options (accuracy_options in accuracy.cpp), for the tasks.
accuracy::Options parse_accuracy_options(const Args& args, const std::string& command) {
    return accuracy_options(parse(args, {"-o", "--report", "--shader-dir", "--backend", "--effect"}, {"--quick", "--quiet"}), args, command);
}

accuracy::Options sweep_options(const Farm& f) {
    Args args;
    for (const auto& a : f.spec.at("accuracy_args")) args.push_back(a.get<std::string>());
    args.insert(args.end(), {"-o", f.dir.string()});
    return parse_accuracy_options(args, "candela farm sweep");
}

json sweep_spec(const Args& args) {
    // Scenes, the report and the shader folder resolve on the nodes as they do here.
    const Args accuracy_args = pass_on(args, {"-o", "--sbatch", "--report", "--shader-dir", "--backend", "--effect"}, {"-o", "--sbatch"},
                                       {"--dry-run", "--submit", "--wait"}, {"--report", "--shader-dir"}, nullptr);
    Args check = accuracy_args;
    check.insert(check.end(), {"-o", "."});
    const accuracy::Options o = parse_accuracy_options(check, "candela farm sweep");  // bad options fail here, not on the cluster
    const std::vector<accuracy::Task> plan = accuracy::plan(o);
    if (plan.empty()) throw bad_input("farm sweep: no section to run (see --effect and the scenes given)");
    json s;
    s["kind"] = "sweep";
    s["tasks"] = static_cast<int>(plan.size());
    s["accuracy_args"] = accuracy_args;
    json labels = json::array();
    for (const accuracy::Task& t : plan) labels.push_back(t.label);
    s["sections"] = labels;
    return s;
}

int task_sweep(const Farm& f, int i) {
    const accuracy::Options o = sweep_options(f);
    return run_accuracy_section(o, i, f.section(i));
}

int finish_sweep(const Farm& f) {
    std::vector<fs::path> dirs;
    for (int i = 0; i < f.tasks(); ++i) dirs.push_back(f.section(i));
    return assemble_accuracy(sweep_options(f), dirs);
}

// --- writing and submitting a farm ---------------------------------------------------------

struct FarmFiles {
    std::vector<std::pair<fs::path, std::string>> files;  // path, content
    std::vector<fs::path> executables;
};

FarmFiles farm_files(const Farm& f) {
    FarmFiles out;
    const std::string exe = f.spec.at("candela").get<std::string>();
    const std::string dir = f.dir.string();
    const int n = f.tasks();
    const std::string name = "candela-" + f.kind();
    std::string tasks;
    for (int i = 0; i < n; ++i)
        tasks += sh_quote(exe) + " farm task " + sh_quote(dir) + " " + std::to_string(i) + " >> " + sh_quote(f.log(i).string()) + " 2>&1\n";
    out.files.emplace_back(f.dir / "tasks.txt", tasks);
    // Any scheduler with a task index: run-task.sh INDEX (GNU parallel, Kubernetes indexed jobs,
    // HTCondor's $(Process); docs/farm.md).
    out.files.emplace_back(f.dir / "run-task.sh", "#!/bin/sh\n# Task INDEX of this farm (0.." + std::to_string(n - 1) +
                                                      "), its output appended to logs/task_INDEX.log.\n"
                                                      "exec " + sh_quote(exe) + " farm task " + sh_quote(dir) + " \"$1\" >> " +
                                                      sh_quote((f.dir / "logs").string()) + "/task_\"$1\".log 2>&1\n");
    out.executables.push_back(f.dir / "run-task.sh");
    std::string extra;
    for (const auto& a : f.spec.at("sbatch_args")) extra += "#SBATCH " + a.get<std::string>() + "\n";
    out.files.emplace_back(f.dir / "slurm" / "array.sbatch",
                           "#!/bin/sh\n#SBATCH --job-name=" + name + "\n#SBATCH --array=0-" + std::to_string(n - 1) +
                               "\n#SBATCH --output=" + (f.dir / "logs").string() + "/task_%a.log\n#SBATCH --open-mode=append\n" + extra +
                               "exec " + sh_quote(exe) + " farm task " + sh_quote(dir) + " \"$SLURM_ARRAY_TASK_ID\"\n");
    out.files.emplace_back(f.dir / "slurm" / "finish.sbatch",
                           "#!/bin/sh\n#SBATCH --job-name=" + name + "-finish\n#SBATCH --output=" + (f.dir / "logs").string() +
                               "/finish.log\n#SBATCH --open-mode=append\n" + extra + "exec " + sh_quote(exe) + " farm finish " + sh_quote(dir) + "\n");
    // afterany, not afterok: the finishing job also runs when a task failed, and says which and why.
    out.files.emplace_back(f.dir / "submit-slurm.sh",
                           "#!/bin/sh\n# Submits the array and the job that finishes after it (what 'candela farm submit' does).\nset -e\n"
                           "array=$(sbatch --parsable " + sh_quote((f.dir / "slurm" / "array.sbatch").string()) + ")\n"
                           "sbatch --parsable --dependency=afterany:\"${array%%;*}\" " + sh_quote((f.dir / "slurm" / "finish.sbatch").string()) + "\n");
    out.executables.push_back(f.dir / "submit-slurm.sh");
    return out;
}

// Runs argv (PATH lookup), returns its exit status; stdout into `out`.
int run_program(const std::vector<std::string>& argv, std::string& out) {
    int pipefd[2];
    if (pipe(pipefd) != 0) throw Error(ExitCode::internal, "farm: pipe failed");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipefd[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, pipefd[0]);
    std::vector<char*> cargv;
    for (const std::string& a : argv) cargv.push_back(const_cast<char*>(a.c_str()));
    cargv.push_back(nullptr);
    pid_t pid = 0;
    const int err = posix_spawnp(&pid, argv[0].c_str(), &actions, nullptr, cargv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(pipefd[1]);
    if (err != 0) {
        close(pipefd[0]);
        throw bad_input("farm: cannot run " + argv[0] + " (" + std::strerror(err) + "): is Slurm's client installed and on PATH?");
    }
    char buf[4096];
    for (ssize_t n; (n = read(pipefd[0], buf, sizeof buf)) > 0;) out.append(buf, static_cast<size_t>(n));
    close(pipefd[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// Waits for a Slurm job to end and returns its exit code (128 + signal if killed; 1 if it ended
// otherwise, e.g. cancelled or timed out). Polls `scontrol show job` every half second: sbatch
// --wait polls with growing intervals and returned up to 12 s after the job had ended here.
int wait_for_job(const std::string& job) {
    static const char* const kEnded[] = {"COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "PREEMPTED", "OUT_OF_MEMORY", "BOOT_FAIL", "DEADLINE"};
    for (int misses = 0;;) {
        std::string out;
        const int rc = run_program({"scontrol", "show", "job", "-o", job}, out);
        const auto field = [&](const std::string& name) {
            const size_t at = out.find(" " + name + "=");
            if (at == std::string::npos) return std::string();
            const size_t from = at + name.size() + 2;
            return out.substr(from, out.find_first_of(" \n", from) - from);
        };
        const std::string state = field("JobState");
        if (rc != 0 || state.empty()) {
            // The controller forgets a job MinJobAge (default 300 s) after it ended.
            if (++misses > 10) throw Error(ExitCode::internal, "farm: Slurm no longer knows job " + job + " (scontrol show job: " + out + ")");
        } else {
            misses = 0;
            for (const char* ended : kEnded)
                if (state == ended) {
                    int code = 0, signal = 0;
                    std::sscanf(field("ExitCode").c_str(), "%d:%d", &code, &signal);
                    return signal ? 128 + signal : state == "COMPLETED" || code ? code : 1;
                }
        }
        usleep(500000);
    }
}

// Submits the array, then the finishing job after it; with wait, blocks until the finishing job
// ends and returns its exit code.
int submit(const Farm& f, bool wait) {
    std::string out;
    const auto t0 = std::chrono::steady_clock::now();
    int rc = run_program({"sbatch", "--parsable", (f.dir / "slurm" / "array.sbatch").string()}, out);
    const std::string array = out.substr(0, out.find_first_of(";\n"));
    if (rc != 0 || array.empty()) throw Error(ExitCode::internal, "farm: sbatch of the array failed (exit " + std::to_string(rc) + "): " + out);
    std::printf("farm: submitted %d tasks as Slurm array job %s\n", f.tasks(), array.c_str());
    out.clear();
    rc = run_program({"sbatch", "--parsable", "--dependency=afterany:" + array, (f.dir / "slurm" / "finish.sbatch").string()}, out);
    const std::string job = out.substr(0, out.find_first_of(";\n"));
    if (rc != 0 || job.empty()) throw Error(ExitCode::internal, "farm: sbatch of the finishing job failed (exit " + std::to_string(rc) + "): " + out);
    std::printf("farm: the finishing job %s runs after it: %s\n", job.c_str(), (f.dir / "logs" / "finish.log").string().c_str());
    if (!wait) return 0;
    std::fflush(stdout);
    rc = wait_for_job(job);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("farm: finishing job %s ended with exit %d after %.1f s since submission; its log:\n%s", job.c_str(), rc, s,
                log_tail(f.dir / "logs" / "finish.log", 20).c_str());
    return rc == 0 ? 0 : static_cast<int>(ExitCode::internal);
}

int farm_create(const std::string& kind, const Args& args) {
    std::vector<std::string> with_value = {"-o", "--sbatch"};
    std::vector<std::string> flags = {"--dry-run", "--submit", "--wait"};
    if (kind == "reference") {
        const std::vector<std::string> r = reference_value_options();
        with_value.insert(with_value.end(), r.begin(), r.end());
        with_value.push_back("--shards");
        flags.insert(flags.end(), kSceneSetupFlags.begin(), kSceneSetupFlags.end());
        flags.push_back("--batch-stats");
    } else {
        with_value.insert(with_value.end(), {"--report", "--shader-dir", "--backend", "--effect"});
        flags.insert(flags.end(), {"--quick", "--quiet"});
    }
    const Parsed p = parse(args, with_value, flags);
    if (!p.has("-o")) throw bad_input("farm " + kind + " needs -o DIR (the farm directory: tasks, scripts, logs and outputs)");
    if (p.flags.count("--wait") && !p.flags.count("--submit")) throw bad_input("--wait goes with --submit");
    Farm f;
    f.dir = fs::absolute(p.get("-o")).lexically_normal();
    f.spec = kind == "reference" ? reference_spec(p, args) : sweep_spec(args);
    f.spec["candela_farm"] = kFarmVersion;
    f.spec["candela"] = self_exe().string();
    f.spec["sbatch_args"] = p.all("--sbatch");
    const FarmFiles files = farm_files(f);
    if (p.flags.count("--dry-run")) {
        for (const auto& [path, text] : files.files)
            if (path.extension() == ".sbatch") std::printf("# %s\n%s\n", path.string().c_str(), text.c_str());
        std::printf("# then: sbatch --dependency=afterany:<array job id> %s\n", (f.dir / "slurm" / "finish.sbatch").string().c_str());
        return 0;
    }
    // A rerun with the same job reuses the directory (complete tasks skip); another job does not
    // overwrite it.
    const fs::path spec_file = f.dir / "farm.json";
    if (fs::exists(spec_file)) {
        json old;
        try {
            old = json::parse(read_text(spec_file));
        } catch (const json::exception&) {
        }
        if (old != f.spec)
            throw bad_input(spec_file.string() + " describes another farm job: give another -o, or delete the directory to start again");
        std::printf("farm: %s holds this job already: tasks whose output is complete will be skipped\n", f.dir.string().c_str());
    }
    for (const char* sub : {"logs", "slurm"}) fs::create_directories(f.dir / sub);
    write_file(spec_file, f.spec.dump(2) + "\n");
    for (const auto& [path, text] : files.files) {
        const bool exec = std::find(files.executables.begin(), files.executables.end(), path) != files.executables.end();
        write_file(path, text, exec);
    }
    std::printf("farm: %d %s tasks in %s\n  Slurm:       candela farm submit %s   (or sh %s)\n  any other:   %s INDEX for INDEX in 0..%d (tasks.txt lists them), then candela farm finish %s\n",
                f.tasks(), kind == "reference" ? "shard" : "section", f.dir.string().c_str(), sh_quote(f.dir.string()).c_str(),
                sh_quote((f.dir / "submit-slurm.sh").string()).c_str(), sh_quote((f.dir / "run-task.sh").string()).c_str(), f.tasks() - 1,
                sh_quote(f.dir.string()).c_str());
    if (p.flags.count("--submit")) return submit(f, p.flags.count("--wait") > 0);
    return 0;
}

int farm_task(const Args& args) {
    const Parsed p = parse(args, {}, {});
    if (p.positional.size() != 2) throw bad_input("farm task needs DIR and INDEX");
    const Farm f = load_farm(p.positional[0]);
    const int i = parse_int("farm task INDEX", p.positional[1], 0, f.tasks() - 1);
    const auto t0 = std::chrono::steady_clock::now();
    char host[256] = "";
    gethostname(host, sizeof host - 1);
    std::printf("task %d of %d (%s) on %s\n", i, f.tasks(), f.kind().c_str(), host);
    std::fflush(stdout);
    const int rc = f.kind() == "reference" ? task_reference(f, i) : task_sweep(f, i);
    std::printf("task %d: exit %d after %.1f s\n", i, rc, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return rc;
}

int farm_status(const Farm& f, bool quiet_if_done) {
    const auto missing = missing_tasks(f);
    if (missing.empty()) {
        if (!quiet_if_done) std::printf("farm: all %d tasks of %s are complete\n", f.tasks(), f.dir.string().c_str());
        return 0;
    }
    std::fprintf(stderr, "farm: %zu of %d tasks of %s are not complete:\n", missing.size(), f.tasks(), f.dir.string().c_str());
    for (const auto& [i, why] : missing)
        std::fprintf(stderr, "  task %d: %s\n  its log %s:\n%s", i, why.c_str(), f.log(i).string().c_str(), log_tail(f.log(i), 5).c_str());
    std::fprintf(stderr, "  rerun them with 'candela farm submit %s' (complete tasks are skipped) or run-task.sh INDEX\n", f.dir.string().c_str());
    return static_cast<int>(ExitCode::internal);
}

}  // namespace

int cmd_farm(const Args& args) {
    if (args.empty()) throw bad_input("farm needs reference, sweep, task, finish, status or submit (see 'candela --help')");
    const std::string what = args[0];
    const Args rest(args.begin() + 1, args.end());
    if (what == "reference" || what == "sweep") return farm_create(what, rest);
    if (what == "task") return farm_task(rest);
    if (what == "finish" || what == "status" || what == "submit") {
        const Parsed p = parse(rest, {}, what == "submit" ? std::vector<std::string>{"--wait"} : std::vector<std::string>{});
        if (p.positional.size() != 1) throw bad_input("farm " + what + " needs DIR");
        const Farm f = load_farm(p.positional[0]);
        if (what == "submit") return submit(f, p.flags.count("--wait") > 0);
        if (what == "status") return farm_status(f, false);
        // A failed or missing task: say which, why and what its log says, and stop.
        if (const int rc = farm_status(f, true); rc != 0) return rc;
        return f.kind() == "reference" ? finish_reference(f) : finish_sweep(f);
    }
    throw bad_input("farm: unknown action '" + what + "' (reference, sweep, task, finish, status or submit)");
}

}  // namespace candela::cli
