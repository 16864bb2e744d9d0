#include "math/transform.h"

#include <cmath>

#include "math/constants.h"
#include "util/error.h"

namespace lt {

Matrix4 Matrix4::identity() {
    Matrix4 r;
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1;
    return r;
}

Matrix4 Matrix4::operator*(const Matrix4& o) const {
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += m[i][k] * o.m[k][j];
            r.m[i][j] = s;
        }
    return r;
}

Matrix4 Matrix4::transposed() const {
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = m[j][i];
    return r;
}

bool Matrix4::isFinite() const {
    for (const auto& row : m)
        for (double v : row)
            if (!std::isfinite(v)) return false;
    return true;
}

bool Matrix4::inverse(Matrix4& out) const {
    // Gauss-Jordan elimination with partial pivoting, in double.
    double a[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            a[i][j] = m[i][j];
            a[i][j + 4] = (i == j) ? 1.0 : 0.0;
        }
    double scale = 0;
    for (const auto& row : m)
        for (double v : row) scale = std::max(scale, std::abs(v));
    if (!(scale > 0) || !isFinite()) return false;
    for (int c = 0; c < 4; ++c) {
        int pivot = c;
        for (int r = c + 1; r < 4; ++r)
            if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
        if (std::abs(a[pivot][c]) < 1e-14 * scale) return false;
        if (pivot != c)
            for (int j = 0; j < 8; ++j) std::swap(a[c][j], a[pivot][j]);
        const double inv = 1.0 / a[c][c];
        for (int j = 0; j < 8; ++j) a[c][j] *= inv;
        for (int r = 0; r < 4; ++r)
            if (r != c) {
                const double f = a[r][c];
                if (f != 0)
                    for (int j = 0; j < 8; ++j) a[r][j] -= f * a[c][j];
            }
    }
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out.m[i][j] = a[i][j + 4];
    return true;
}

Transform Transform::fromMatrix(const Matrix4& m) {
    Matrix4 inv;
    if (!m.isFinite()) throw Error("transform matrix is not finite");
    if (!m.inverse(inv)) throw Error("transform matrix is singular");
    return {m, inv};
}

Transform Transform::translate(const Vec3& t) {
    Matrix4 m = Matrix4::identity(), inv = Matrix4::identity();
    for (int i = 0; i < 3; ++i) {
        m.m[i][3] = t[i];
        inv.m[i][3] = -t[i];
    }
    return {m, inv};
}

Transform Transform::scale(const Vec3& s) {
    if (s.x == 0 || s.y == 0 || s.z == 0 || !isFinite(s)) throw Error("scale factors must be finite and non-zero");
    Matrix4 m = Matrix4::identity(), inv = Matrix4::identity();
    for (int i = 0; i < 3; ++i) {
        m.m[i][i] = s[i];
        inv.m[i][i] = 1.0 / s[i];
    }
    return {m, inv};
}

Transform Transform::rotate(const Vec3& axisIn, double angleDeg) {
    const double len = length(axisIn);
    if (!(len > 0)) throw Error("rotation axis must be non-zero");
    const Vec3 a = axisIn / len;
    const double s = std::sin(degToRad(angleDeg)), c = std::cos(degToRad(angleDeg));
    Matrix4 m = Matrix4::identity();
    m.m[0][0] = a.x * a.x + (1 - a.x * a.x) * c;
    m.m[0][1] = a.x * a.y * (1 - c) - a.z * s;
    m.m[0][2] = a.x * a.z * (1 - c) + a.y * s;
    m.m[1][0] = a.x * a.y * (1 - c) + a.z * s;
    m.m[1][1] = a.y * a.y + (1 - a.y * a.y) * c;
    m.m[1][2] = a.y * a.z * (1 - c) - a.x * s;
    m.m[2][0] = a.x * a.z * (1 - c) - a.y * s;
    m.m[2][1] = a.y * a.z * (1 - c) + a.x * s;
    m.m[2][2] = a.z * a.z + (1 - a.z * a.z) * c;
    return {m, m.transposed()};
}

Transform Transform::lookAt(const Vec3& origin, const Vec3& target, const Vec3& up) {
    const Vec3 d = target - origin;
    if (!(length(d) > 0)) throw Error("lookat: origin and target coincide");
    const Vec3 dir = normalize(d);
    const Vec3 l = cross(up, dir);
    if (!(length(l) > 1e-12)) throw Error("lookat: up vector is parallel to the viewing direction");
    const Vec3 left = normalize(l);
    const Vec3 newUp = cross(dir, left);
    Matrix4 m = Matrix4::identity();
    for (int i = 0; i < 3; ++i) {
        m.m[i][0] = left[i];
        m.m[i][1] = newUp[i];
        m.m[i][2] = dir[i];
        m.m[i][3] = origin[i];
    }
    return fromMatrix(m);
}

Vec3 Transform::point(const Vec3& p) const {
    const auto& a = m_.m;
    const double x = a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3];
    const double y = a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3];
    const double z = a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3];
    const double w = a[3][0] * p.x + a[3][1] * p.y + a[3][2] * p.z + a[3][3];
    return w == 1.0 ? Vec3(x, y, z) : Vec3(x, y, z) / w;
}

Vec3 Transform::vector(const Vec3& v) const {
    const auto& a = m_.m;
    return {a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z, a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
            a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z};
}

Vec3 Transform::normal(const Vec3& n) const {
    const auto& a = inv_.m;
    return {a[0][0] * n.x + a[1][0] * n.y + a[2][0] * n.z, a[0][1] * n.x + a[1][1] * n.y + a[2][1] * n.z,
            a[0][2] * n.x + a[1][2] * n.y + a[2][2] * n.z};
}

double Transform::determinant3x3() const {
    const auto& a = m_.m;
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

bool Transform::isIdentity() const {
    const Matrix4 id = Matrix4::identity();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (m_.m[i][j] != id.m[i][j]) return false;
    return true;
}

} // namespace lt
