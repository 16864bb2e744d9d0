#include "bsdf/twosided.h"

#include <algorithm>

#include "util/error.h"

namespace lt {

namespace {
Vec3 mirrorZ(const Vec3& w) { return {w.x, w.y, -w.z}; }
Vec3 toFront(const Vec3& wi, const Vec3& w) { return wi.z < 0 ? mirrorZ(w) : w; }
} // namespace

TwoSided::TwoSided(TwoSidedParams params) : p_(std::move(params)) {
    if (!p_.front) throw Error("twosided: no nested BSDF");
    if (!p_.back) p_.back = p_.front;
    if (p_.front->hasTransmission() || p_.back->hasTransmission())
        throw Error("twosided: nested BSDF '" + (p_.front->hasTransmission() ? p_.front : p_.back)->typeName() +
                    "' transmits light; only reflecting BSDFs can be made two-sided");
}

Spectrum TwoSided::eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const {
    return side(wi).eval(toFront(wi, wi), toFront(wi, wo), uv, mode);
}

double TwoSided::pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const {
    return side(wi).pdf(toFront(wi, wi), toFront(wi, wo), uv);
}

std::optional<BsdfSample> TwoSided::sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                           const Vec2& u) const {
    auto s = side(wi).sample(toFront(wi, wi), uv, mode, uLobe, u);
    if (s) s->wo = toFront(wi, s->wo);
    return s;
}

std::optional<BsdfSample> TwoSided::deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const {
    auto s = side(wi).deltaEval(toFront(wi, wi), toFront(wi, wo), uv, mode);
    if (s) s->wo = wo;
    return s;
}

Lobes TwoSided::lobes() const { return p_.front->lobes() | p_.back->lobes(); }

double TwoSided::roughness(const Vec2& uv) const { return std::min(p_.front->roughness(uv), p_.back->roughness(uv)); }

} // namespace lt
