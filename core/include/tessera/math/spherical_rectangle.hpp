#pragma once
// Uniform sampling of the solid angle a rectangle subtends (Ureña, Fajardo and King, "An
// Area-Preserving Parametrization for Spherical Rectangles", EGSR 2013). Sampling the
// solid angle instead of the area removes the 1/r^2 of points close to an area light,
// which made a ceiling 1 cm above a light's back face a source of fireflies.
#include <cmath>

#include "tessera/math/vec.hpp"

namespace tessera {

struct SphericalRectangle {
  vec3 origin;               // the reference point
  vec3 x, y, z;              // the rectangle's frame; z points from the rectangle's plane to origin
  float x0, x1, y0, y1, z0;  // the rectangle in that frame, z0 <= 0
  float b0, b1, k;
  float solid_angle = 0.0f;

  // `corner`, `edge_u` and `edge_v` give the rectangle; the edges must be orthogonal.
  TESSERA_HD static SphericalRectangle make(const vec3& corner, const vec3& edge_u,
                                            const vec3& edge_v, const vec3& origin) {
    SphericalRectangle r;
    r.origin = origin;
    const float eu = glm::length(edge_u), ev = glm::length(edge_v);
    r.x = edge_u / eu;
    r.y = edge_v / ev;
    r.z = glm::cross(r.x, r.y);
    const vec3 d = corner - origin;
    r.z0 = glm::dot(d, r.z);
    if (r.z0 > 0.0f) {
      r.z = -r.z;
      r.z0 = -r.z0;
    }
    r.x0 = glm::dot(d, r.x);
    r.y0 = glm::dot(d, r.y);
    r.x1 = r.x0 + eu;
    r.y1 = r.y0 + ev;
    const vec3 v00(r.x0, r.y0, r.z0), v01(r.x0, r.y1, r.z0), v10(r.x1, r.y0, r.z0),
        v11(r.x1, r.y1, r.z0);
    // Normals of the planes through the origin and each edge; the interior angles between
    // them by atan2, not acos: a rectangle seen edge-on has angles near 0 and pi, where
    // acos of a float cosine is off by ~sqrt(1e-7) and the solid angle by 1% (chi-square
    // test RectangleGrazing in tests/unit/render/light_sampling_test.cpp).
    const vec3 n0 = safe_normalize(glm::cross(v00, v10));
    const vec3 n1 = safe_normalize(glm::cross(v10, v11));
    const vec3 n2 = safe_normalize(glm::cross(v11, v01));
    const vec3 n3 = safe_normalize(glm::cross(v01, v00));
    const float g0 = angle_between(n0, -n1);
    const float g1 = angle_between(n1, -n2);
    const float g2 = angle_between(n2, -n3);
    const float g3 = angle_between(n3, -n0);
    r.b0 = n0.z;
    r.b1 = n2.z;
    r.k = 2.0f * kPi - g2 - g3;
    r.solid_angle = g0 + g1 - r.k;
    return r;
  }

  // The point on the rectangle for (u, v) in [0, 1)^2; uniform in solid angle.
  TESSERA_HD vec3 sample(float u, float v) const {
    const float au = u * solid_angle + k;
    const float sin_au = std::sin(au);
    const float fu = (std::cos(au) * b0 - b1) / sin_au;
    float cu = (fu > 0.0f ? 1.0f : -1.0f) / std::sqrt(fu * fu + b0 * b0);
    cu = glm::clamp(cu, -1.0f, 1.0f);
    float xu = -(cu * z0) / glm::max(std::sqrt(1.0f - cu * cu), 1e-7f);
    xu = glm::clamp(xu, x0, x1);
    const float d = std::sqrt(xu * xu + z0 * z0);
    const float h0 = y0 / std::sqrt(d * d + y0 * y0);
    const float h1 = y1 / std::sqrt(d * d + y1 * y1);
    const float hv = h0 + v * (h1 - h0);
    const float hv2 = hv * hv;
    const float yv = hv2 < 1.0f - 1e-6f ? (hv * d) / std::sqrt(1.0f - hv2) : y1;
    return origin + xu * x + glm::clamp(yv, y0, y1) * y + z0 * z;
  }

 private:
  TESSERA_HD static vec3 safe_normalize(const vec3& v) {
    const float len2 = glm::dot(v, v);
    return len2 > 0.0f ? v / std::sqrt(len2) : vec3(0.0f);
  }
  TESSERA_HD static float angle_between(const vec3& a, const vec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
  }
};

}  // namespace tessera
