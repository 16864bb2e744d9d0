// The options the library's registries declare (util/option_spec.h: a mutation's, an estimator's) as command-line
// options: each spec becomes one CLI11 option with its flag, help and type, checked by the spec's own parse, so a
// bad value is refused as every other option's is (one line, CLI11's exit code). Specs that several rows share
// (--mis of BDPT and the path tracer) are one option.
#pragma once

#include <CLI/CLI.hpp>

#include <map>
#include <string>
#include <vector>

#include "util/error.h"
#include "util/option_spec.h"

namespace lt::tool {

class RegistryOptions {
public:
    // Adds the options of `specs` to `app`, in order, once per flag.
    void add(CLI::App& app, const std::vector<OptionSpec>& specs) {
        for (const OptionSpec& spec : specs) {
            if (texts_.count(spec.flag)) continue;
            specs_.push_back(spec);
            app.add_option(spec.flag, texts_[spec.flag], spec.help)
                ->type_name(spec.typeName)
                ->check(CLI::Validator(
                    [parse = spec.parse](std::string& text) -> std::string {
                        try {
                            (void)parse(text);
                            return {};
                        } catch (const Error& e) {
                            return e.what();
                        }
                    },
                    ""));
        }
    }

    // The values of the options given on the command line (their defaults are the library's to fill in).
    [[nodiscard]] OptionValues given(const CLI::App& app) const {
        OptionValues values;
        for (const OptionSpec& spec : specs_)
            if (app.count(spec.flag)) values.set(spec, texts_.at(spec.flag), true);
        return values;
    }

    // Throws "FLAG is an option of WHOSE" for an option of `specs` given on the command line that `chosen` lacks.
    static void refuseOthers(const CLI::App& app, const std::vector<OptionSpec>& specs,
                             const std::vector<OptionSpec>& chosen, const std::string& whose) {
        for (const OptionSpec& spec : specs) {
            bool mine = false;
            for (const OptionSpec& c : chosen)
                mine |= c.flag == spec.flag;
            if (!mine && app.count(spec.flag)) throw Error(spec.flag + " is an option of " + whose);
        }
    }

private:
    std::vector<OptionSpec> specs_;
    std::map<std::string, std::string> texts_; // the text given, by flag
};

} // namespace lt::tool
