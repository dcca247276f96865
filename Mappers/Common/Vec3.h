// Small fixed-size vectors for the kernels (float in hot loops, double where cancellation
// matters).
#ifndef RayMappers_Vec3_h
#define RayMappers_Vec3_h

#include <algorithm>
#include <array>
#include <cmath>

namespace raymappers
{

template<typename T>
struct Vec3
{
  T x = 0, y = 0, z = 0;
  constexpr Vec3() = default;
  constexpr Vec3(T a, T b, T c)
    : x(a)
    , y(b)
    , z(c)
  {
  }
  template<typename U>
  explicit constexpr Vec3(const Vec3<U>& o)
    : x(static_cast<T>(o.x))
    , y(static_cast<T>(o.y))
    , z(static_cast<T>(o.z))
  {
  }
  explicit constexpr Vec3(const std::array<T, 3>& a)
    : x(a[0])
    , y(a[1])
    , z(a[2])
  {
  }
  T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  Vec3 operator+(const Vec3& o) const { return { x + o.x, y + o.y, z + o.z }; }
  Vec3 operator-(const Vec3& o) const { return { x - o.x, y - o.y, z - o.z }; }
  Vec3 operator-() const { return { -x, -y, -z }; }
  Vec3 operator*(T s) const { return { x * s, y * s, z * s }; }
  Vec3 operator*(const Vec3& o) const { return { x * o.x, y * o.y, z * o.z }; }
  Vec3& operator+=(const Vec3& o)
  {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
};

using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;

template<typename T>
inline T dot(const Vec3<T>& a, const Vec3<T>& b)
{
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template<typename T>
inline Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b)
{
  return { a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}
template<typename T>
inline T length(const Vec3<T>& a)
{
  return std::sqrt(dot(a, a));
}
template<typename T>
inline Vec3<T> normalize(const Vec3<T>& a)
{
  const T l = length(a);
  return l > T(0) ? a * (T(1) / l) : a;
}
template<typename T>
inline Vec3<T> min(const Vec3<T>& a, const Vec3<T>& b)
{
  return Vec3<T>(std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z));
}
template<typename T>
inline Vec3<T> max(const Vec3<T>& a, const Vec3<T>& b)
{
  return Vec3<T>(std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z));
}
template<typename T>
inline bool isFinite(const Vec3<T>& a)
{
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

} // namespace raymappers

#endif
