#include "run/estimator_registry.h"

#include "gradient/gradient_path_tracer.h"
#include "gradient/path_reusing.h"
#include "sampling/bdpt.h"
#include "sampling/path_tracer.h"
#include "util/error.h"

namespace lt {

namespace {

const EstimatorKind* const Kinds[] = {
    &Bdpt::Kind,               //
    &PathTracer::Kind,         //
    &PathReusing::Kind,        //
    &GradientPathTracer::Kind, //
};

} // namespace

EstimatorKinds estimatorKinds() { return Kinds; }

std::vector<const EstimatorKind*> estimatorKinds(const std::vector<std::string>& names) {
    std::vector<const EstimatorKind*> out;
    for (const auto& name : names) {
        const EstimatorKind* found = nullptr;
        for (const EstimatorKind* k : estimatorKinds())
            if (k->name == name) found = k;
        if (!found) throw Error("no pixel estimator named '" + name + "'");
        out.push_back(found);
    }
    return out;
}

nlohmann::json estimatorParameters(const EstimatorKind& kind, OptionValues values) {
    values.setDefaults(kind.options);
    nlohmann::json out = kind.record.is_object() ? kind.record : nlohmann::json::object();
    out.update(values.record(kind.options));
    return out;
}

} // namespace lt
