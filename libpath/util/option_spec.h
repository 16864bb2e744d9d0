// Options that a part of the library owns: a mutation's step size, an estimator's tile. Each is declared once, by
// the registry row of what it belongs to, with its name, help, default and the one check of its value; the tools
// turn the declarations into command-line options (tools/common/registry_options.h), and the library reads the
// values by their key. The same values, keyed the same way, are what the output files record as parameters.
#pragma once

#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "util/error.h"
#include "util/number_text.h"

namespace lt {

struct OptionSpec {
    std::string flag;        // on the command line: "--hslt-gamma"
    std::string key;         // in the values and the files' parameters: "hslt_gamma"
    std::string help;        // what it does, its default and its range
    std::string typeName;    // how --help shows its value: "NUMBER", "on|off", "MIN,MAX"
    std::string defaultText; // the value when the option is not given, as it would be written
    // The value of the text as it is recorded, or throws lt::Error saying what is wrong with it (the caller adds
    // the option's name).
    std::function<nlohmann::json(const std::string&)> parse;
};

// The values of a set of options, by key: those given and the defaults of the others.
class OptionValues {
public:
    // Sets `key` from `text` through the spec's parse; throws "FLAG: what is wrong".
    void set(const OptionSpec& spec, const std::string& text) {
        try {
            values_[spec.key] = spec.parse(text);
        } catch (const Error& e) {
            throw Error(spec.flag + ": " + e.what());
        }
    }
    // The defaults of `specs` for every key not set yet.
    void setDefaults(const std::vector<OptionSpec>& specs) {
        for (const auto& s : specs)
            if (!values_.contains(s.key)) set(s, s.defaultText);
    }
    // A value the library derives before use (a pre-run's measurement), for whoever reads the values next.
    void put(const std::string& key, nlohmann::json value) { values_[key] = std::move(value); }
    [[nodiscard]] bool has(const std::string& key) const { return values_.contains(key); }
    [[nodiscard]] const nlohmann::json& at(const std::string& key) const {
        if (!values_.contains(key)) throw Error("no value for option '" + key + "'");
        return values_.at(key);
    }
    [[nodiscard]] double number(const std::string& key) const { return at(key).get<double>(); }
    // The values of `specs`, for a file's parameters.
    [[nodiscard]] nlohmann::json record(const std::vector<OptionSpec>& specs) const {
        nlohmann::json out = nlohmann::json::object();
        for (const auto& s : specs)
            out[s.key] = at(s.key);
        return out;
    }

private:
    nlohmann::json values_ = nlohmann::json::object();
};

namespace option {

// A finite number for which `ok` holds; `what` says which numbers those are ("must lie in (0, 1]").
inline std::function<nlohmann::json(const std::string&)> number(std::function<bool(double)> ok, std::string what) {
    return [ok = std::move(ok), what = std::move(what)](const std::string& text) -> nlohmann::json {
        const auto v = numberFromText(text);
        if (!v || !std::isfinite(*v) || !ok(*v)) throw Error(what + ", got " + text);
        return *v;
    };
}
inline auto positive() {
    return number([](double v) { return v > 0; }, "must be a positive number");
}
inline auto nonNegative() {
    return number([](double v) { return v >= 0; }, "must be a number >= 0");
}

// A whole number in [lo, hi], written as one ("6", not "6.0"), recorded as an integer.
inline std::function<nlohmann::json(const std::string&)> integer(int lo, int hi) {
    return [lo, hi](const std::string& text) -> nlohmann::json {
        int v = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (error != std::errc() || end != text.data() + text.size() || v < lo || v > hi)
            throw Error("must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " +
                        text);
        return v;
    };
}

// One of `names`, recorded as given.
inline std::function<nlohmann::json(const std::string&)> choice(std::vector<std::string> names) {
    return [names = std::move(names)](const std::string& text) -> nlohmann::json {
        for (const auto& n : names)
            if (text == n) return text;
        std::string list;
        for (const auto& n : names)
            list += (list.empty() ? "" : ", ") + n;
        throw Error("must be one of " + list + ", got " + text);
    };
}

// "on" or "off", recorded as true or false.
inline nlohmann::json onOff(const std::string& text) {
    if (text == "on") return true;
    if (text == "off") return false;
    throw Error("must be on or off, got " + text);
}

// `count` numbers separated by commas, each finite, for which `ok` holds of the list.
inline std::function<nlohmann::json(const std::string&)>
numbers(size_t count, std::function<bool(const std::vector<double>&)> ok, std::string what) {
    return [count, ok = std::move(ok), what = std::move(what)](const std::string& text) -> nlohmann::json {
        std::vector<double> v;
        size_t at = 0;
        for (;;) {
            const size_t comma = text.find(',', at);
            const auto x = numberFromText(std::string_view(text).substr(at, comma - at));
            if (!x || !std::isfinite(*x)) throw Error(what + ", got " + text);
            v.push_back(*x);
            if (comma == std::string::npos) break;
            at = comma + 1;
        }
        if (v.size() != count || !ok(v)) throw Error(what + ", got " + text);
        return v;
    };
}

} // namespace option

} // namespace lt
