#pragma once
// __float128 arithmetic for the reference intersectors: 113-bit significands, so products
// of the 24-bit float inputs are exact and the references' own rounding is ~1e-34 relative,
// far below the float and double errors being measured.
#include <quadmath.h>

#include <glm/glm.hpp>

namespace tessera::stress {

using quad = __float128;

inline quad qsqrt(quad x) {
  return sqrtq(x);
}
inline quad qabs(quad x) {
  return x < 0 ? -x : x;
}
inline double to_double(quad x) {
  return static_cast<double>(x);
}

struct QVec {
  quad x = 0, y = 0, z = 0;

  QVec() = default;
  QVec(quad x_, quad y_, quad z_) : x(x_), y(y_), z(z_) {}
  explicit QVec(const glm::vec3& v) : x(v.x), y(v.y), z(v.z) {}
  explicit QVec(const glm::dvec3& v) : x(v.x), y(v.y), z(v.z) {}

  QVec operator+(const QVec& o) const { return {x + o.x, y + o.y, z + o.z}; }
  QVec operator-(const QVec& o) const { return {x - o.x, y - o.y, z - o.z}; }
  QVec operator*(quad s) const { return {x * s, y * s, z * s}; }
  QVec operator-() const { return {-x, -y, -z}; }
  quad operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  glm::dvec3 to_dvec3() const { return glm::dvec3(to_double(x), to_double(y), to_double(z)); }
};

inline QVec operator*(quad s, const QVec& v) {
  return v * s;
}
inline quad dot(const QVec& a, const QVec& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline QVec cross(const QVec& a, const QVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline quad length(const QVec& v) {
  return qsqrt(dot(v, v));
}
inline QVec normalize(const QVec& v) {
  return v * (quad(1) / length(v));
}

// A ray with exact (quad) origin and direction: the float ray converted exactly, or the
// exact image of a world ray under an instance's inverse transform.
struct QRay {
  QVec origin;
  QVec direction;
};

}  // namespace tessera::stress
