// The options the library's registries declare (util/option_spec.h: a mutation's, an estimator's) as command-line
// options: each spec becomes one CLI11 option with its flag, help and type, checked by the spec's own parse, so a
// bad value is refused as every other option's is (one line, CLI11's exit code). Specs that several rows share
// (--mis of BDPT and the path tracer) are one option.
#pragma once

#include <CLI/CLI.hpp>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "common/tool.h"
#include "util/error.h"
#include "util/option_spec.h"

namespace lt::tool {

class RegistryOptions {
public:
    // Adds the options of `specs` to `app`, in order, once per flag. A spec whose default lists several values
    // ("MIN,MAX") takes them as one word with commas or as that many words, as CLI11 lists do.
    void add(CLI::App& app, const std::vector<OptionSpec>& specs) {
        for (const OptionSpec& spec : specs) {
            if (texts_.count(spec.flag)) continue;
            specs_.push_back(spec);
            const int values = 1 + int(std::count(spec.defaultText.begin(), spec.defaultText.end(), ','));
            CLI::Option* o = app.add_option(spec.flag, texts_[spec.flag], spec.help)->type_name(spec.typeName);
            if (values == 1)
                o->check(optionCheck("", spec.parse));
            else
                o->expected(values)->delimiter(','); // checked whole, by given()
        }
    }

    // The values of the options given on the command line (their defaults are the library's to fill in); throws
    // lt::Error "FLAG: what is wrong" for a value its spec refuses.
    [[nodiscard]] OptionValues given(const CLI::App& app) const {
        OptionValues values;
        for (const OptionSpec& spec : specs_)
            if (app.count(spec.flag)) {
                std::string text;
                for (const auto& part : texts_.at(spec.flag))
                    text += (text.empty() ? "" : ",") + part;
                values.set(spec, text);
            }
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
    std::map<std::string, std::vector<std::string>> texts_; // the words given, by flag
};

} // namespace lt::tool
