// Affine transforms as 4x4 double matrices (row-major, column vectors: p' = M p), with the inverse kept
// alongside so that normals transform by the inverse transpose without a numerical inversion per use.
#pragma once

#include <array>

#include "math/vec.h"

namespace lt {

struct Matrix4 {
    std::array<std::array<double, 4>, 4> m{};

    static Matrix4 identity();
    [[nodiscard]] Matrix4 operator*(const Matrix4& o) const;
    [[nodiscard]] Matrix4 transposed() const;
    // Inverse by cofactors in double; returns false for a singular (|det| ~ 0) or non-finite matrix.
    [[nodiscard]] bool inverse(Matrix4& out) const;
    [[nodiscard]] bool isFinite() const;
};

class Transform {
public:
    Transform() : m_(Matrix4::identity()), inv_(Matrix4::identity()) {}
    Transform(const Matrix4& m, const Matrix4& inv) : m_(m), inv_(inv) {}
    // Throws lt::Error when m is singular or not finite.
    static Transform fromMatrix(const Matrix4& m);

    static Transform translate(const Vec3& t);
    static Transform scale(const Vec3& s);
    // Rotation by angleDeg degrees about axis (right-handed, Rodrigues).
    static Transform rotate(const Vec3& axis, double angleDeg);
    // Mitsuba's lookAt: the camera-to-world frame with columns (left, up', dir, origin),
    // left = normalize(cross(up, dir)), up' = cross(dir, left).
    static Transform lookAt(const Vec3& origin, const Vec3& target, const Vec3& up);

    [[nodiscard]] Transform operator*(const Transform& o) const { return {m_ * o.m_, o.inv_ * inv_}; }
    [[nodiscard]] Transform inverse() const { return {inv_, m_}; }

    [[nodiscard]] Vec3 point(const Vec3& p) const;
    [[nodiscard]] Vec3 vector(const Vec3& v) const;
    // Normals transform with the inverse transpose; the result is not normalized.
    [[nodiscard]] Vec3 normal(const Vec3& n) const;
    [[nodiscard]] const Matrix4& matrix() const { return m_; }
    [[nodiscard]] const Matrix4& inverseMatrix() const { return inv_; }
    [[nodiscard]] double determinant3x3() const;
    [[nodiscard]] bool isIdentity() const;

private:
    Matrix4 m_, inv_;
};

} // namespace lt
