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
  // Whether the reference point lies close to the rectangle's plane for its extent (a
  // corner more than 16 |z0| away along x or y): the sample is then taken in double
  // (sample_near_plane).
  bool near_plane = false;

  // The rectangle seen from `origin`, given by a corner, its unit edge directions x and y
  // (orthogonal), its normal z = x cross y and its edge lengths: a light's frame, which the
  // quad keeps (Quad::make) instead of forming it per shading point.
  TESSERA_HD static SphericalRectangle make(const vec3& corner, const vec3& x, const vec3& y,
                                            const vec3& z, float eu, float ev, const vec3& origin) {
    SphericalRectangle r;
    r.set(corner, x, y, z, eu, ev, origin);
    return r;
  }

  // make(...) written into this one. A light sampler fills its caller's rectangle this way:
  // assigned from make's result, the copy read the new fields back as 16-byte loads just
  // after they were stored one by one, which waits for the stores to reach the cache
  // (0.7% of a path-traced sample's time on the converge scene two_lights; store_ray in
  // geometry/ray.hpp says more).
  TESSERA_HD void set(const vec3& corner, const vec3& x_direction, const vec3& y_direction,
                      const vec3& z_direction, float eu, float ev, const vec3& reference) {
    SphericalRectangle& r = *this;
    const vec3 x = x_direction, y = y_direction, z = z_direction;
    const vec3 origin = reference;
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
    const float extent = glm::max(glm::max(std::fabs(r.x0), std::fabs(r.x1)),
                                  glm::max(std::fabs(r.y0), std::fabs(r.y1)));
    r.near_plane = extent > kNearPlaneRatio * az0;
  }

  // Beyond this ratio of a corner's in-plane coordinate to |z0|, float loses more than
  // about 1e-5 of the coordinate: xu = -cu z0 / sqrt(1 - cu^2) has 1 - cu^2 ~ (z0 / xu)^2,
  // so its float rounding (6e-8) becomes 6e-8 (xu / z0)^2 relative to it, and likewise
  // 1 - hv^2 for yv. A point 4 mm below a light's plane landed up to 7 cm from where it
  // belongs, which banded the sampled directions (chi-square test RectangleGrazing).
  static constexpr float kNearPlaneRatio = 16.0f;

  // The point on the rectangle for (u, v) in [0, 1)^2; uniform in solid angle.
  TESSERA_HD vec3 sample(float u, float v) const {
    const vec2 p = sample_coordinates(u, v);
    return origin + p.x * x + p.y * y + z0 * z;
  }

  // The unit direction from the reference point to sample(u, v), and its distance. hv, the
  // sampled sine of the direction's elevation towards y, is the direction's y component
  // itself: with c = sqrt(1 - hv^2) / sqrt(xu^2 + z0^2) the direction is (xu c, hv, z0 c)
  // and the distance 1 / c, so the point's y coordinate (a square root and a division) and
  // its distance (another pair) stay off the sampler's dependency chain.
  TESSERA_HD void sample_direction(float u, float v, vec3& wi, float& distance) const {
    if (!near_plane) [[likely]] {
      float xu, hv, d2;
      sample_xu_hv(u, v, xu, hv, d2);
      if (direction_from(xu, hv, d2, 1e-6f, wi, distance)) [[likely]]
        return;
    } else {
      double xu, hv, d2;
      near_plane_xu_hv(u, v, xu, hv, d2);
      if (direction_from(xu, hv, d2, 1e-12, wi, distance)) return;
    }
    // Along y's edge (cos^2 of the elevation lost to rounding): from the clamped point.
    const vec2 p = sample_coordinates(u, v);
    distance = std::sqrt(p.x * p.x + p.y * p.y + z0 * z0);
    const float inverse = 1.0f / distance;
    wi = (p.x * inverse) * x + (p.y * inverse) * y + (z0 * inverse) * z;
  }

  // The direction (xu c, hv, z0 c) and distance 1 / c of sample_direction, unless
  // 1 - hv^2 is below `min_cos2` (where its rounding dominates it).
  template <typename Real>
  TESSERA_HD bool direction_from(Real xu, Real hv, Real d2, Real min_cos2, vec3& wi,
                                 float& distance) const {
    const Real cos2 = Real(1) - hv * hv;
    if (!(cos2 >= min_cos2)) return false;
    const Real c = std::sqrt(cos2 / d2);
    wi = static_cast<float>(xu * c) * x + static_cast<float>(hv) * y +
         static_cast<float>(z0 * c) * z;
    distance = static_cast<float>(Real(1) / c);
    return true;
  }

  // The sample's coordinates (xu, yv) along x and y in the rectangle's frame.
  TESSERA_HD vec2 sample_coordinates(float u, float v) const {
    if (near_plane) [[unlikely]]
      return sample_near_plane(u, v);
    float xu, hv, d2;
    sample_xu_hv(u, v, xu, hv, d2);
    const float hv2 = hv * hv;
    const float yv = hv2 < 1.0f - 1e-6f ? (hv * std::sqrt(d2)) / std::sqrt(1.0f - hv2) : y1;
    return vec2(xu, glm::clamp(yv, y0, y1));
  }

  // The far-from-the-plane sample in float: xu, the sine hv of the elevation towards y,
  // and d2 = xu^2 + z0^2.
  TESSERA_HD void sample_xu_hv(float u, float v, float& xu, float& hv, float& d2) const {
    const float au = u * solid_angle + k;
    float sin_au, cos_au;
    fast_sincos(au, sin_au, cos_au);
    // The paper's x from its fu = (cos b0 - b1) / sin and cu = sign(fu) / sqrt(fu^2 + b0^2),
    // xu = -cu z0 / sqrt(1 - cu^2), folded into one square root and one division:
    // xu = -sign(fu) |sin| z0 / sqrt(num^2 - (1 - b0^2) sin^2) with num = cos b0 - b1. The
    // sample is a chain of dependent square roots and divisions, and each one taken out of
    // it is time (the light sampler was a third of the colour-bleed box's wall clock,
    // perf's cpu-clock samples, against a sixth of its instructions). A vanishing denominator
    // gives an infinite xu, which the clamp below takes to the rectangle's edge, as the
    // paper's clamps did.
    const float num = cos_au * b0 - b1;
    const float n = num * num - (1.0f - b0 * b0) * (sin_au * sin_au);
    xu = -z0 * (num > 0.0f ? sin_au : -sin_au) / std::sqrt(glm::max(n, 1e-30f));
    xu = glm::clamp(xu, x0, x1);
    d2 = xu * xu + z0 * z0;
    const float h0 = y0 / std::sqrt(d2 + y0 * y0);
    const float h1 = y1 / std::sqrt(d2 + y1 * y1);
    hv = h0 + v * (h1 - h0);
  }

  // sample_coordinates in double, with 1 - b0^2 and the heights formed without cancellation, for
  // points near the rectangle's plane. Its error is 1e-16 (x / z0)^2 of a coordinate, so the
  // map is exact to float precision up to ratios of about 10^4. What remains is the float
  // rounding of k and the solid angle (angle sums near pi), about 1e-3 of the solid angle at
  // the 3e-4 sr below which the lights sample by area (light_detail::spherical_usable).
  // Points this close to a light's plane are few: on the box, whose ceiling is 1 cm above
  // its light, the path costs 0.4% of the render's instructions.
  TESSERA_HD vec2 sample_near_plane(float u, float v) const {
    double xu, hv, d2;
    near_plane_xu_hv(u, v, xu, hv, d2);
    const double one_minus_hv_sq = 1.0 - hv * hv;
    double yv = one_minus_hv_sq > 0.0 ? hv * std::sqrt(d2 / one_minus_hv_sq)
                                      : (hv < 0.0 ? double{y0} : double{y1});
    yv = glm::clamp(yv, double{y0}, double{y1});
    return vec2(static_cast<float>(xu), static_cast<float>(yv));
  }

  // sample_xu_hv in double, for sample_near_plane.
  TESSERA_HD void near_plane_xu_hv(float u, float v, double& xu, double& hv, double& d2) const {
    const double zd = z0, z2 = zd * zd, y0d = y0, y1d = y1;
    const double b0d = -y0d / std::sqrt(z2 + y0d * y0d);
    const double b1d = y1d / std::sqrt(z2 + y1d * y1d);
    const double one_minus_b0_sq = z2 / (z2 + y0d * y0d);
    const double au = static_cast<double>(u) * solid_angle + k;
    double sin_au, cos_au;
    fast_sincos(au, sin_au, cos_au);
    const double num = cos_au * b0d - b1d;
    const double n = num * num - one_minus_b0_sq * (sin_au * sin_au);
    xu = -zd * (num > 0.0 ? sin_au : -sin_au) / std::sqrt(n > 1e-300 ? n : 1e-300);
    xu = glm::clamp(xu, double{x0}, double{x1});
    d2 = xu * xu + z2;
    const double h0 = y0d / std::sqrt(d2 + y0d * y0d);
    const double h1 = y1d / std::sqrt(d2 + y1d * y1d);
    hv = h0 + static_cast<double>(v) * (h1 - h0);
  }
};

}  // namespace tessera
