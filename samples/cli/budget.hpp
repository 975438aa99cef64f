#pragma once
// --error-budget E on render, info and bench frame (docs/error-budget.md), and
// `candela bench error-budget` (measure the ladder on scenes, fit the model, evaluate it).
#include <cstdio>
#include <optional>
#include <string>

#include "accuracy/error_budget.hpp"
#include "commands.hpp"
#include "options.hpp"

namespace candela::cli {

// The options a command with --error-budget accepts (with a value).
extern const std::vector<std::string> kBudgetOptions;

// --error-budget E [--budget-model FILE], read before any GL work so that bad input exits 2 first.
struct BudgetRequest {
    double budget = 0;
    budget::Model model;
    std::string model_label;  // "built-in" or the file
};
// nullopt without --error-budget. Throws bad_input naming the option: a budget that is not a
// number in (0, 1], a model file that cannot be read, --effects given with --error-budget (the
// budget chooses the effects), --budget-model without --error-budget.
std::optional<BudgetRequest> budget_request(const Parsed& p);

// Measures the scene's statistics from the camera (a tiny trace) and chooses the candidate. `text`
// gets the lines that say so: the statistics, the chosen candidate and the runner-up it rejected,
// and with `all_candidates` one line per candidate (info).
budget::Choice choose_for_scene(const BudgetRequest& r, const Scene& scene, const ShaderLibrary& shaders, const std::string& camera,
                                int width, int height, bool all_candidates, std::string& text);
// The chosen candidate's settings, then the command's --path and --set over them.
RenderSettings budget_settings(const budget::Choice& c, const Parsed& p);

// `candela bench error-budget ...` (cmd_budget.cpp).
int bench_error_budget(const Args& args);

}  // namespace candela::cli
