#pragma once
// Uniform sampling of the solid angle a rectangle subtends (Ureña, Fajardo and King, "An
// Area-Preserving Parametrization for Spherical Rectangles", EGSR 2013). Sampling the
// solid angle instead of the area removes the 1/r^2 of points close to an area light,
// which made a ceiling 1 cm above a light's back face a source of fireflies.
#include <cmath>

#include "tessera/math/fast_trig.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

struct SphericalRectangle {
  vec3 origin;               // the reference point
  vec3 x, y, z;              // the rectangle's frame; z points from the rectangle's plane to origin
  float x0, x1, y0, y1, z0;  // the rectangle in that frame, z0 <= 0
  float b0, b1, k;
  float solid_angle = 0.0f;

  // The rectangle seen from `origin`, given by a corner, its unit edge directions x and y
  // (orthogonal), its normal z = x cross y and its edge lengths: a light's frame, which the
  // quad keeps (Quad::make) instead of forming it per shading point.
  TESSERA_HD static SphericalRectangle make(const vec3& corner, const vec3& x, const vec3& y,
                                            const vec3& z, float eu, float ev, const vec3& origin) {
    SphericalRectangle r;
    r.origin = origin;
    r.x = x;
    r.y = y;
    r.z = z;
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
    // The planes through the origin and each edge have normals n0 ~ (0, z0, -y0),
    // n1 ~ (-z0, 0, x1), n2 ~ (0, -z0, y1), n3 ~ (z0, 0, -x0) in this frame, so the
    // interior angle at corner (x, y) is atan2(|z0| |(x, y, z0)|, +-x y) in closed form:
    // no normalisation, and precise near 0 and pi, where acos of a float cosine is off by
    // ~sqrt(1e-7) and a rectangle seen edge-on lost 1% of its solid angle (chi-square test
    // RectangleGrazing in tests/unit/render/light_sampling_test.cpp).
    // Only the sums g0 + g1 and g2 + g3 matter (k and the solid angle), so each pair is
    // one atan2 of the product of the two corners' (cos, sin) pairs: a sum lies in
    // (0, 2 pi), so a negative atan2 means the sum is past pi.
    const float az0 = std::fabs(r.z0), z02 = r.z0 * r.z0;
    const auto corner_pair = [&](float x, float y, float cosine_sign) {
      return vec2(cosine_sign * x * y, az0 * std::sqrt(x * x + y * y + z02));
    };
    const auto angle_sum = [](const vec2& a, const vec2& b) {
      const float t = fast_atan2(a.x * b.y + a.y * b.x, a.x * b.x - a.y * b.y);
      return t < 0.0f ? t + 2.0f * kPi : t;
    };
    const float g01 = angle_sum(corner_pair(r.x1, r.y0, 1.0f), corner_pair(r.x1, r.y1, -1.0f));
    const float g23 = angle_sum(corner_pair(r.x0, r.y1, 1.0f), corner_pair(r.x0, r.y0, -1.0f));
    r.b0 = -r.y0 / std::sqrt(z02 + r.y0 * r.y0);
    r.b1 = r.y1 / std::sqrt(z02 + r.y1 * r.y1);
    r.k = 2.0f * kPi - g23;
    r.solid_angle = g01 - r.k;
    return r;
  }

  // The point on the rectangle for (u, v) in [0, 1)^2; uniform in solid angle.
  TESSERA_HD vec3 sample(float u, float v) const {
    const float au = u * solid_angle + k;
    float sin_au, cos_au;
    fast_sincos(au, sin_au, cos_au);
    // The paper's x from its fu = (cos b0 - b1) / sin and cu = sign(fu) / sqrt(fu^2 + b0^2),
    // xu = -cu z0 / sqrt(1 - cu^2), folded into one square root and one division:
    // xu = -sign(fu) |sin| z0 / sqrt(num^2 - (1 - b0^2) sin^2) with num = cos b0 - b1. The
    // sample is a chain of dependent square roots and divisions, and each one taken out of
    // it is time (the light sampler was a third of the colour-bleed box's wall clock,
    // perf's cpu-clock samples, against a sixth of its instructions). A vanishing denominator gives
    // an infinite xu, which the clamp below takes to the rectangle's edge, as the paper's clamps
    // did.
    const float num = cos_au * b0 - b1;
    const float n = num * num - (1.0f - b0 * b0) * (sin_au * sin_au);
    float xu = -z0 * (num > 0.0f ? sin_au : -sin_au) / std::sqrt(glm::max(n, 1e-30f));
    xu = glm::clamp(xu, x0, x1);
    const float d2 = xu * xu + z0 * z0;
    const float d = std::sqrt(d2);
    const float h0 = y0 / std::sqrt(d2 + y0 * y0);
    const float h1 = y1 / std::sqrt(d2 + y1 * y1);
    const float hv = h0 + v * (h1 - h0);
    const float hv2 = hv * hv;
    const float yv = hv2 < 1.0f - 1e-6f ? (hv * d) / std::sqrt(1.0f - hv2) : y1;
    return origin + xu * x + glm::clamp(yv, y0, y1) * y + z0 * z;
  }
};

}  // namespace tessera
