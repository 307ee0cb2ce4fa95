#pragma once
// Uniform sampling of the solid angle a triangle subtends (Arvo, "Stratified Sampling of
// Spherical Triangles", SIGGRAPH 1995). Like the spherical rectangle, it removes the 1/r^2
// of area sampling for points close to an emitting triangle (a ceiling a few centimetres
// above a mesh light).
#include <cmath>

#include "tessera/math/fast_trig.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

struct SphericalTriangle {
  vec3 a{0.0f}, b{0.0f}, c{0.0f};  // unit directions from the reference point to the corners
  float alpha = 0.0f;              // the spherical triangle's angle at a
  float cos_c = 0.0f;              // cosine of the arc from a to b
  float solid_angle = 0.0f;

  TESSERA_HD static SphericalTriangle make(const vec3& p0, const vec3& p1, const vec3& p2,
                                           const vec3& origin) {
    SphericalTriangle t;
    t.set(p0, p1, p2, origin);
    return t;
  }

  // make(...) written into this one, for a light sampler's caller-held triangle: assigning
  // make's result copied it through stores and wider loads that stall
  // (SphericalRectangle::set says more).
  TESSERA_HD void set(const vec3& p0, const vec3& p1, const vec3& p2, const vec3& origin) {
    SphericalTriangle& t = *this;
    t.a = unit(p0 - origin);
    t.b = unit(p1 - origin);
    t.c = unit(p2 - origin);
    // Normals of the great circles through each pair of corners; the angle at a corner is
    // the angle between the two circles meeting there. atan2 keeps angles near 0 and pi
    // precise, where acos of a float cosine does not.
    const vec3 n_ab = unit(glm::cross(t.a, t.b));
    const vec3 n_bc = unit(glm::cross(t.b, t.c));
    const vec3 n_ca = unit(glm::cross(t.c, t.a));
    t.alpha = angle_between(n_ab, -n_ca);
    const float beta = angle_between(n_bc, -n_ab);
    const float gamma = angle_between(n_ca, -n_bc);
    t.cos_c = glm::dot(t.a, t.b);
    t.solid_angle = glm::max(0.0f, t.alpha + beta + gamma - kPi);
  }

  // The unit direction for (u1, u2) in [0, 1)^2; uniform in solid angle.
  TESSERA_HD vec3 sample(float u1, float u2) const {
    // u1 picks the sub-triangle (a, b, c_hat) of area u1 * solid_angle: c_hat on arc a-c.
    const float area = u1 * solid_angle;
    float s, t, sin_alpha, cos_alpha;
    fast_sincos(area - alpha, s, t);
    fast_sincos(alpha, sin_alpha, cos_alpha);
    const float u = t - cos_alpha;
    const float v = s + sin_alpha * cos_c;
    const float denominator = (v * s + u * t) * sin_alpha;
    float q = denominator != 0.0f ? ((v * t - u * s) * cos_alpha - v) / denominator : 1.0f;
    q = glm::clamp(q, -1.0f, 1.0f);
    const vec3 c_hat =
        q * a + std::sqrt(glm::max(0.0f, 1.0f - q * q)) * unit(c - glm::dot(c, a) * a);
    // u2 picks the point on the arc from b to c_hat, uniform in the sub-triangle's area.
    const float z = 1.0f - u2 * (1.0f - glm::dot(c_hat, b));
    return z * b + std::sqrt(glm::max(0.0f, 1.0f - z * z)) * unit(c_hat - glm::dot(c_hat, b) * b);
  }

 private:
  TESSERA_HD static vec3 unit(const vec3& v) {
    const float len2 = glm::dot(v, v);
    return len2 > 0.0f ? v / std::sqrt(len2) : vec3(0.0f);
  }
  TESSERA_HD static float angle_between(const vec3& x, const vec3& y) {
    return fast_atan2(glm::length(glm::cross(x, y)), glm::dot(x, y));
  }
};

}  // namespace tessera
