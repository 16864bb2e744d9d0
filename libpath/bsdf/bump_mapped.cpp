#include "bsdf/bump_mapped.h"

#include "util/error.h"

namespace lt {

BumpMappedBsdf::BumpMappedBsdf(std::shared_ptr<const Texture> displacement, std::shared_ptr<const Bsdf> nested)
    : displacement_(std::move(displacement)), nested_(std::move(nested)) {
    if (!displacement_ || !nested_) throw Error("bumpmap needs a displacement texture and a nested BSDF");
}

} // namespace lt
