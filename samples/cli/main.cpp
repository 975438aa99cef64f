#include <algorithm>
#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "core/error.hpp"

int main(int argc, char** argv) {
    using namespace candela;
    cli::Args args(argv + 1, argv + argc);
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
        cli::print_usage();
        return args.empty() ? static_cast<int>(ExitCode::bad_input) : 0;
    }
    const std::string command = args[0];
    args.erase(args.begin());
    // `candela COMMAND --help` (anywhere after the command): that command's usage, exit 0.
    if (command != "--version" && std::any_of(args.begin(), args.end(), [](const std::string& a) { return a == "--help" || a == "-h"; })) {
        if (cli::print_command_usage(command)) return 0;
        std::fprintf(stderr, "candela: unknown command '%s' (try 'candela --help')\n", command.c_str());
        return static_cast<int>(ExitCode::bad_input);
    }
    try {
        if (command == "--version") return cli::cmd_version(args);
        if (command == "render") return cli::cmd_render(args);
        if (command == "info") return cli::cmd_info(args);
        if (command == "compare") return cli::cmd_compare(args);
        if (command == "bench") return cli::cmd_bench(args);
        if (command == "merge") return cli::cmd_merge(args);
        if (command == "shaders") return cli::cmd_shaders(args);
        if (command == "view") return cli::cmd_view(args);
        if (command == "batch") return cli::cmd_batch(args);
        if (command == "farm") return cli::cmd_farm(args);
        std::fprintf(stderr, "candela: unknown command '%s' (try 'candela --help')\n", command.c_str());
        return static_cast<int>(ExitCode::bad_input);
    } catch (const Error& e) {
        std::fprintf(stderr, "candela: error: %s\n", e.what());
        return static_cast<int>(e.code());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "candela: internal error: %s\n", e.what());
        return static_cast<int>(ExitCode::internal);
    }
}
