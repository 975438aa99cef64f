#pragma once
// Knob rows: one declaration per knob (name, type, range or choices, help) over a field of an
// options struct. `--set`, `info --knobs`, the stats JSON and the viewer's widgets are all made
// from these rows, so a knob exists exactly once. Values outside the range are rejected with a
// message naming the knob and its range, never clamped.
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string_view>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace candela {

struct RenderSettings;

struct KnobInfo {
    std::string name;   // "ssao.samples"
    std::string type;   // "bool", "int", "float", "choice"
    std::string range;  // "[1, 256]", "full|half", ...
    std::string help;
    double lo = 0.0, hi = 0.0;         // int and float: the valid range
    std::vector<std::string> choices;  // choice: the names, in declaration order
    // What the knob is while the camera moves (the viewer's adaptive quality, reduced level):
    // a number is lowered to `moving` if it is above it; a choice, declared from the finest to
    // the cheapest, goes to `moving` if it comes before it. Empty: the knob stays. Only when the
    // assignment `moving_when` ("knob=value") holds, if given (a knob that else does nothing).
    std::string moving;
    std::string moving_when;
};

struct Knob {
    KnobInfo info;
    std::function<void(RenderSettings&, const std::string&)> set;  // throws bad_input
    std::function<nlohmann::json(const RenderSettings&)> get;
};

// The names of a choice knob's enum, declared once beside the enum: { {"full", X::full}, ... }.
template <class E>
struct ChoiceName {
    const char* name;
    E value;
};

template <class E, std::size_t N>
const char* choice_name(const ChoiceName<E> (&names)[N], E value) {
    for (const auto& c : names)
        if (c.value == value) return c.name;
    return "?";
}

// The value named `text`, if any.
template <class E, std::size_t N>
std::optional<E> parse_choice(const ChoiceName<E> (&names)[N], std::string_view text) {
    for (const auto& c : names)
        if (text == c.name) return c.value;
    return std::nullopt;
}

// Rows over the options struct O, which `access` finds in a RenderSettings.
template <class O>
class KnobRows {
public:
    using Access = O& (*)(RenderSettings&);
    KnobRows(std::string prefix, Access access) : prefix_(std::move(prefix)), access_(access) {}

    KnobRows& integer(const char* name, int O::*field, int lo, int hi, const char* help) {
        KnobInfo info{full(name), "int", "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]", help, double(lo), double(hi), {}, {}, {}};
        const Access access = access_;
        rows.push_back({info,
                        [=](RenderSettings& s, const std::string& v) {
                            try {
                                size_t used = 0;
                                const long x = std::stol(v, &used);
                                if (used == v.size() && x >= lo && x <= hi) {
                                    access(s).*field = static_cast<int>(x);
                                    return;
                                }
                            } catch (const std::exception&) {
                            }
                            reject(info, v);
                        },
                        [=](const RenderSettings& s) { return nlohmann::json(access(const_cast<RenderSettings&>(s)).*field); }});
        return *this;
    }

    KnobRows& real(const char* name, float O::*field, float lo, float hi, const char* help) {
        char range[64];
        std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
        KnobInfo info{full(name), "float", range, help, double(lo), double(hi), {}, {}, {}};
        const Access access = access_;
        rows.push_back({info,
                        [=](RenderSettings& s, const std::string& v) {
                            try {
                                size_t used = 0;
                                const float x = std::stof(v, &used);
                                if (used == v.size() && std::isfinite(x) && x >= lo && x <= hi) {
                                    access(s).*field = x;
                                    return;
                                }
                            } catch (const std::exception&) {
                            }
                            reject(info, v);
                        },
                        [=](const RenderSettings& s) { return nlohmann::json(access(const_cast<RenderSettings&>(s)).*field); }});
        return *this;
    }

    KnobRows& boolean(const char* name, bool O::*field, const char* help) {
        KnobInfo info{full(name), "bool", "0|1|true|false|on|off", help, 0.0, 1.0, {}, {}, {}};
        const Access access = access_;
        rows.push_back({info,
                        [=](RenderSettings& s, const std::string& v) {
                            if (v == "1" || v == "true" || v == "on") access(s).*field = true;
                            else if (v == "0" || v == "false" || v == "off") access(s).*field = false;
                            else reject(info, v);
                        },
                        [=](const RenderSettings& s) { return nlohmann::json(access(const_cast<RenderSettings&>(s)).*field); }});
        return *this;
    }

    // A choice among the enum E's named values; JSON and messages use the names.
    template <class E, std::size_t N>
    KnobRows& choice(const char* name, E O::*field, const ChoiceName<E> (&names)[N], const char* help) {
        std::vector<ChoiceName<E>> table(std::begin(names), std::end(names));
        KnobInfo info{full(name), "choice", "", help, 0.0, double(N - 1), {}, {}, {}};
        for (const auto& c : table) {
            if (!info.range.empty()) info.range += '|';
            info.range += c.name;
            info.choices.push_back(c.name);
        }
        const Access access = access_;
        rows.push_back({info,
                        [=](RenderSettings& s, const std::string& v) {
                            for (const auto& c : table)
                                if (v == c.name) {
                                    access(s).*field = c.value;
                                    return;
                                }
                            reject(info, v);
                        },
                        [=](const RenderSettings& s) {
                            const E value = access(const_cast<RenderSettings&>(s)).*field;
                            for (const auto& c : table)
                                if (c.value == value) return nlohmann::json(c.name);
                            return nlohmann::json(nullptr);
                        }});
        return *this;
    }

    // The last row's value while the camera moves (KnobInfo::moving), if `when` holds.
    KnobRows& while_moving(std::string value, std::string when = {}) {
        rows.back().info.moving = std::move(value);
        rows.back().info.moving_when = std::move(when);
        return *this;
    }

    std::vector<Knob> rows;

private:
    std::string full(const char* name) const { return prefix_ + "." + name; }
    [[noreturn]] static void reject(const KnobInfo& k, const std::string& value) {
        throw bad_input("--set " + k.name + "=" + value + ": expected " + k.type + " in " + k.range);
    }
    std::string prefix_;
    Access access_;
};

}  // namespace candela
