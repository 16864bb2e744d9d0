// Small value types for 2- and 3-vectors. Geometry computations in libpath run in double
// (manifold walks need ~1e-7 relative precision); meshes store float for Embree.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace lt {

template <class T> struct TVec2 {
    T x = 0, y = 0;
    constexpr TVec2() = default;
    constexpr TVec2(T x_, T y_) : x(x_), y(y_) {}
    template <class U> constexpr explicit TVec2(const TVec2<U>& o) : x(T(o.x)), y(T(o.y)) {}
    constexpr T operator[](std::size_t i) const { return i == 0 ? x : y; }
    constexpr T& operator[](std::size_t i) { return i == 0 ? x : y; }
    constexpr TVec2 operator+(const TVec2& o) const { return {x + o.x, y + o.y}; }
    constexpr TVec2 operator-(const TVec2& o) const { return {x - o.x, y - o.y}; }
    constexpr TVec2 operator*(T s) const { return {x * s, y * s}; }
    constexpr TVec2 operator/(T s) const { return {x / s, y / s}; }
    constexpr bool operator==(const TVec2&) const = default;
};

template <class T> struct TVec3 {
    T x = 0, y = 0, z = 0;
    constexpr TVec3() = default;
    constexpr TVec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    template <class U> constexpr explicit TVec3(const TVec3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}
    constexpr T operator[](std::size_t i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr T& operator[](std::size_t i) { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr TVec3 operator-() const { return {-x, -y, -z}; }
    constexpr TVec3 operator+(const TVec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr TVec3 operator-(const TVec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr TVec3 operator*(const TVec3& o) const { return {x * o.x, y * o.y, z * o.z}; }
    constexpr TVec3 operator/(const TVec3& o) const { return {x / o.x, y / o.y, z / o.z}; }
    constexpr TVec3 operator*(T s) const { return {x * s, y * s, z * s}; }
    constexpr TVec3 operator/(T s) const { return {x / s, y / s, z / s}; }
    constexpr TVec3& operator+=(const TVec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    constexpr TVec3& operator-=(const TVec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    constexpr TVec3& operator*=(const TVec3& o) { x *= o.x; y *= o.y; z *= o.z; return *this; }
    constexpr TVec3& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
    constexpr TVec3& operator/=(T s) { x /= s; y /= s; z /= s; return *this; }
    constexpr bool operator==(const TVec3&) const = default;
};

template <class T> constexpr TVec3<T> operator*(T s, const TVec3<T>& v) { return v * s; }
template <class T> constexpr TVec2<T> operator*(T s, const TVec2<T>& v) { return v * s; }

template <class T> constexpr T dot(const TVec3<T>& a, const TVec3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> constexpr T dot(const TVec2<T>& a, const TVec2<T>& b) { return a.x * b.x + a.y * b.y; }
template <class T> constexpr TVec3<T> cross(const TVec3<T>& a, const TVec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> inline T length(const TVec3<T>& v) { return std::sqrt(dot(v, v)); }
template <class T> inline T length(const TVec2<T>& v) { return std::sqrt(dot(v, v)); }
template <class T> constexpr T lengthSquared(const TVec3<T>& v) { return dot(v, v); }
template <class T> inline TVec3<T> normalize(const TVec3<T>& v) { return v / length(v); }
template <class T> constexpr TVec3<T> abs(const TVec3<T>& v) { return {std::abs(v.x), std::abs(v.y), std::abs(v.z)}; }
template <class T> constexpr TVec3<T> min(const TVec3<T>& a, const TVec3<T>& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
template <class T> constexpr TVec3<T> max(const TVec3<T>& a, const TVec3<T>& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
template <class T> constexpr T maxComponent(const TVec3<T>& v) { return std::max(v.x, std::max(v.y, v.z)); }
template <class T> constexpr T minComponent(const TVec3<T>& v) { return std::min(v.x, std::min(v.y, v.z)); }
template <class T> inline bool isFinite(const TVec3<T>& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
template <class T> inline bool isFinite(const TVec2<T>& v) { return std::isfinite(v.x) && std::isfinite(v.y); }

using Vec2d = TVec2<double>;
using Vec2f = TVec2<float>;
using Vec2i = TVec2<int>;
using Vec3d = TVec3<double>;
using Vec3f = TVec3<float>;

// The default precision of libpath's geometry and transport math.
using Vec2 = Vec2d;
using Vec3 = Vec3d;

// Reflect w (pointing away from the surface) about n.
inline Vec3 reflect(const Vec3& w, const Vec3& n) { return 2.0 * dot(w, n) * n - w; }

// The derivative of a normalized vector z / |z| for a change dz, given the unit vector and 1 / |z|:
// (dz - zhat (zhat . dz)) / |z|. Normal fields, directions toward a moving vertex
// and half vectors all differentiate through it.
inline Vec3 normalizedDerivative(const Vec3& unit, double invLength, const Vec3& dz) {
    return (dz - unit * dot(unit, dz)) * invLength;
}

} // namespace lt
