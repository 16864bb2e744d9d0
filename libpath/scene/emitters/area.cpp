// Mitsuba's `area` emitter: uniform radiance L leaving the front side of a shape (where dot(n, d) > 0,
// n the geometric normal after flipNormals), zero behind it.
#include <cmath>

#include "math/constants.h"
#include "math/frame.h"
#include "math/warp.h"
#include "scene/emitter.h"
#include "scene/measure.h"

namespace lt {

namespace {

class AreaEmitter final : public Emitter {
public:
    // The shape is copied: the scene's shape vector may still grow (and reallocate) after the emitter
    // is made, and emissive shapes are small.
    AreaEmitter(const Shape& shape, const Spectrum& radiance) : shape_(shape), radiance_(radiance) {}

    [[nodiscard]] uint8_t flags() const override { return EmitterSurface; }
    [[nodiscard]] std::string typeName() const override { return "area"; }

    // Two strategies (Shirley et al. 1996, "Monte Carlo techniques for direct lighting calculations";
    // pbrt-v3 Sphere::Sample(ref, u)):
    // * a sphere seen from outside: directions uniform in the cone it subtends. Uniform area sampling
    //   wastes half its samples on the hidden side and its d^2/|cos| weight explodes at the silhouette;
    //   for the small lights of Veach's MIS scene (radius 0.05 at distance ~20) the cone is exact.
    // * everything else (triangles, disks, a reference point inside or on a sphere): uniform by area,
    //   converted to solid angle.
    [[nodiscard]] DirectSample sampleDirect(const Vec3& ref, const Vec2& u) const override {
        DirectSample ds;
        double pdf;
        if (useCone(ref)) {
            pdf = sampleCone(ref, u, ds.p, ds.n);
            ds.coords = shape_.analyticCoords(ds.p);
            ds.magnitude = shape_.pointAt(0, ds.coords).magnitude;
        } else {
            const PositionSample ps = shape_.samplePosition(u);
            ds.p = ps.p;
            ds.n = ps.n;
            ds.coords = ps.coords;
            ds.prim = ps.prim;
            ds.magnitude = ps.magnitude;
            pdf = pdfAreaToSolidAngle(ps.pdfArea, ref, ps.p, ps.n);
        }
        const Vec3 v = ds.p - ref;
        ds.dist = length(v);
        if (!(ds.dist > 0) || !(pdf > 0)) return {};
        ds.wi = v / ds.dist;
        ds.pdf = pdf;
        ds.value = evalSurface(ds.p, ds.n, -ds.wi);
        return ds;
    }

    // Exactly the density sampleDirect uses for p. For a sphere seen from outside, the cone strategy
    // only produces the visible cap (the first intersection of each direction in the cone), so a point
    // on the far side has density 0. Such a point is never the first hit from ref, and it cannot send
    // light to ref (its front side faces away from ref, or is occluded by the sphere when the normals are
    // flipped), so no path with nonzero contribution is affected.
    [[nodiscard]] double pdfDirect(const Vec3& ref, const Vec3& p, const Vec3& n, const Vec3& dir) const override {
        (void)dir;
        if (useCone(ref)) {
            const Vec3 c = shape_.center();
            const double r2 = sqr(shape_.radius());
            // On the visible cap iff dot(p - c, ref - c) >= r^2 (equality on the silhouette); the
            // relative slack keeps round-off in sampled silhouette points from flipping them to 0.
            if (dot(p - c, ref - c) < r2 * (1 - 1e-6)) return 0;
            return warp::squareToUniformConeNarrowPdf(oneMinusCosThetaMax(ref));
        }
        return pdfAreaToSolidAngle(1.0 / shape_.area(), ref, p, n);
    }

    // Uniform position by area, cosine-weighted direction about the front normal (Veach thesis 10.1:
    // the density that makes L cos / p constant for a diffuse emitter).
    [[nodiscard]] EmissionSample sampleEmission(const Vec2& uPos, const Vec2& uDir) const override {
        const PositionSample ps = shape_.samplePosition(uPos);
        const Vec3 local = warp::squareToCosineHemisphere(uDir);
        EmissionSample es;
        es.p = ps.p;
        es.n = ps.n;
        es.coords = ps.coords;
        es.prim = ps.prim;
        es.d = Frame::fromNormal(ps.n).toWorld(local);
        es.pdfPos = ps.pdfArea;
        es.pdfDir = warp::squareToCosineHemispherePdf(local);
        es.value = es.pdfDir > 0 ? radiance_ : Spectrum();
        return es;
    }

    void pdfEmission(const Vec3& p, const Vec3& n, const Vec3& d, double& pdfPos, double& pdfDir) const override {
        (void)p;
        pdfPos = 1.0 / shape_.area();
        pdfDir = std::max(0.0, dot(n, d)) * InvPi;
    }

    [[nodiscard]] Spectrum evalSurface(const Vec3& p, const Vec3& n, const Vec3& d) const override {
        (void)p;
        return dot(n, d) > 0 ? radiance_ : Spectrum();
    }

    // Lambertian emitter: integral of L cos over the hemisphere is pi L, times the area.
    [[nodiscard]] Spectrum power() const override { return radiance_ * (Pi * shape_.area()); }

private:
    [[nodiscard]] bool useCone(const Vec3& ref) const {
        return shape_.kind() == Shape::Kind::Sphere && lengthSquared(ref - shape_.center()) > sqr(shape_.radius());
    }

    // 1 - cos(thetaMax) of the cone subtended by the sphere, as sin^2 / (1 + cos) so that it stays exact
    // for tiny, distant spheres.
    [[nodiscard]] double oneMinusCosThetaMax(const Vec3& ref) const {
        const double sin2Max = sqr(shape_.radius()) / lengthSquared(shape_.center() - ref);
        return sin2Max / (1 + safeSqrt(1 - sin2Max));
    }

    // Samples a direction uniformly in the subtended cone and returns the point where it first meets the
    // sphere, computed from the angle alpha at the center instead of by ray intersection (pbrt-v4
    // Sphere::Sample: cos(alpha) = sin^2(theta) / sin(thetaMax) + cos(theta) sqrt(1 - sin^2(theta) /
    // sin^2(thetaMax)), free of the cancellation a ray-sphere test suffers when r << distance).
    double sampleCone(const Vec3& ref, const Vec2& u, Vec3& p, Vec3& n) const {
        const Vec3 c = shape_.center();
        const double r = shape_.radius();
        const Vec3 toCenter = c - ref;
        const double dc = length(toCenter);
        const double sinMax = r / dc;
        const double oneMinusCos = oneMinusCosThetaMax(ref);
        const Vec3 local = warp::squareToUniformConeNarrow(u, oneMinusCos);
        const double sin2Theta = local.x * local.x + local.y * local.y;
        const double cosAlpha = std::min(1.0, sin2Theta / sinMax + local.z * safeSqrt(1 - sin2Theta / sqr(sinMax)));
        const double sinAlpha = safeSqrt(1 - cosAlpha * cosAlpha);
        // The point lies at the azimuth of the sampled direction, alpha away from the center->ref axis.
        const double sinTheta = std::sqrt(sin2Theta);
        const double cosPhi = sinTheta > 0 ? local.x / sinTheta : 1.0, sinPhi = sinTheta > 0 ? local.y / sinTheta : 0.0;
        const Frame frame = Frame::fromNormal(toCenter / dc);
        const Vec3 outward = frame.toWorld({sinAlpha * cosPhi, sinAlpha * sinPhi, -cosAlpha});
        p = c + outward * r;
        n = shape_.flipNormals() ? -outward : outward;
        return warp::squareToUniformConeNarrowPdf(oneMinusCos);
    }

    Shape shape_;
    Spectrum radiance_;
};

} // namespace

std::unique_ptr<Emitter> makeAreaEmitter(const Shape& shape, int shapeIndex, const Spectrum& radiance) {
    auto e = std::make_unique<AreaEmitter>(shape, radiance);
    e->shape = shapeIndex;
    return e;
}

} // namespace lt
