#pragma once
/// Vec3<T> for T = float or an xsimd batch: the one small-vector implementation of arbor.
#include "simd/simd.h"

namespace arbor::simd {

template <class T> struct Vec3 {
    T x, y, z;

    Vec3() = default;
    constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    explicit constexpr Vec3(T s) : x(s), y(s), z(s) {}

    T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    const T& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }

    friend Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend Vec3 operator*(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
    friend Vec3 operator*(const Vec3& a, T s) { return {a.x * s, a.y * s, a.z * s}; }
    friend Vec3 operator*(T s, const Vec3& a) { return {a.x * s, a.y * s, a.z * s}; }
    friend Vec3 operator/(const Vec3& a, T s) { return {a.x / s, a.y / s, a.z / s}; }
    friend Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
    Vec3& operator+=(const Vec3& b) { return *this = *this + b; }
    Vec3& operator-=(const Vec3& b) { return *this = *this - b; }
    Vec3& operator*=(T s) { return *this = *this * s; }
};

using Vec3f = Vec3<float>;

template <class T> inline T dot(const Vec3<T>& a, const Vec3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> inline Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> inline T length(const Vec3<T>& a) { return std::sqrt(dot(a, a)); }
template <class T> inline Vec3<T> normalize(const Vec3<T>& a) { return a / length(a); }
template <class T> inline Vec3<T> vmin(const Vec3<T>& a, const Vec3<T>& b) {
    return {rmin(a.x, b.x), rmin(a.y, b.y), rmin(a.z, b.z)};
}
template <class T> inline Vec3<T> vmax(const Vec3<T>& a, const Vec3<T>& b) {
    return {rmax(a.x, b.x), rmax(a.y, b.y), rmax(a.z, b.z)};
}
inline float max_component(const Vec3f& a) { return std::max(a.x, std::max(a.y, a.z)); }
inline int max_axis(const Vec3f& a) { return a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2); }

}  // namespace arbor::simd
