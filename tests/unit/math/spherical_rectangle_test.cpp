// SphericalRectangle::sample folds the paper's steps (Ureña, Fajardo and King 2013) into
// fewer square roots and divisions; this checks it against those steps written out in double
// precision and in float, from the same frame and constants.
#include "tessera/math/spherical_rectangle.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace tessera {
namespace {

// The paper's steps in double from the rectangle's float frame (b0 and b1 recomputed in double:
// their float values lose 1 - b0^2 near the rectangle's plane).
glm::dvec3 paper_sample(const SphericalRectangle& r, double u, double v) {
  const double z2 = double{r.z0} * r.z0;
  const double b0 = -r.y0 / std::sqrt(z2 + double{r.y0} * r.y0);
  const double b1 = r.y1 / std::sqrt(z2 + double{r.y1} * r.y1);
  const double au = u * r.solid_angle + r.k;
  const double fu = (std::cos(au) * b0 - b1) / std::sin(au);
  double cu = (fu > 0.0 ? 1.0 : -1.0) / std::sqrt(fu * fu + b0 * b0);
  cu = std::clamp(cu, -1.0, 1.0);
  double xu = -(cu * r.z0) / std::max(std::sqrt(1.0 - cu * cu), 1e-300);
  xu = std::clamp(xu, double{r.x0}, double{r.x1});
  const double d = std::sqrt(xu * xu + double{r.z0} * r.z0);
  const double h0 = r.y0 / std::sqrt(d * d + double{r.y0} * r.y0);
  const double h1 = r.y1 / std::sqrt(d * d + double{r.y1} * r.y1);
  const double hv = h0 + v * (h1 - h0);
  const double yv = hv * hv < 1.0 ? (hv * d) / std::sqrt(1.0 - hv * hv) : (hv < 0.0 ? r.y0 : r.y1);
  return glm::dvec3(r.origin) + xu * glm::dvec3(r.x) +
         std::clamp(yv, double{r.y0}, double{r.y1}) * glm::dvec3(r.y) +
         double{r.z0} * glm::dvec3(r.z);
}

vec3 paper_sample_float(const SphericalRectangle& r, float u, float v) {
  const float au = u * r.solid_angle + r.k;
  float sin_au, cos_au;
  fast_sincos(au, sin_au, cos_au);
  const float fu = (cos_au * r.b0 - r.b1) / sin_au;
  float cu = (fu > 0.0f ? 1.0f : -1.0f) / std::sqrt(fu * fu + r.b0 * r.b0);
  cu = glm::clamp(cu, -1.0f, 1.0f);
  float xu = -(cu * r.z0) / glm::max(std::sqrt(1.0f - cu * cu), 1e-7f);
  xu = glm::clamp(xu, r.x0, r.x1);
  const float d = std::sqrt(xu * xu + r.z0 * r.z0);
  const float h0 = r.y0 / std::sqrt(d * d + r.y0 * r.y0);
  const float h1 = r.y1 / std::sqrt(d * d + r.y1 * r.y1);
  const float hv = h0 + v * (h1 - h0);
  const float hv2 = hv * hv;
  const float yv = hv2 < 1.0f - 1e-6f ? (hv * d) / std::sqrt(1.0f - hv2) : r.y1;
  return r.origin + xu * r.x + glm::clamp(yv, r.y0, r.y1) * r.y + r.z0 * r.z;
}

// The float sampler is ill-conditioned near grazing (a point 4 mm below the light's plane
// landed up to 7 cm from where double precision puts it, whichever float form computed it), so
// such points take the double path (near_plane). Per shading point, over 20 samples, the
// folded form's worst distance from the double-precision point is at most 5e-4 on a 1 x 0.75
// light wherever it subtends the 3e-4 sr the lights sample it from (points from 1 mm to 1 km
// below it, beside it and nearly level with it), and
// no larger than the paper's float steps' plus 1e-4 wherever the float path runs; over all
// points its mean is no larger than theirs. The light sampler's direction and distance
// (sample_direction, which takes the direction's y component from the sampled height
// instead of forming the point) reach a point within the same bound.
TEST(SphericalRectangle, SampleIsAsCloseToThePapersStepsInDoubleAsTheyAreInFloat) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_real_distribution<float> spread(-3.0f, 3.0f);
  // A 1 x 0.75 rectangle at y = 1, edges along x and z.
  const vec3 corner(-0.5f, 1.0f, -0.25f), x(1.0f, 0.0f, 0.0f), y(0.0f, 0.0f, 1.0f);
  int points = 0, near_plane_points = 0;
  double sum_folded = 0.0, sum_paper = 0.0;
  for (int i = 0; i < 400; ++i) {
    // Below the rectangle from 1 mm to 1 km, beside it and nearly level with it.
    const vec3 origin(spread(rng), 1.0f - std::pow(10.0f, spread(rng)), spread(rng));
    const SphericalRectangle r =
        SphericalRectangle::make(corner, x, y, glm::cross(x, y), 1.0f, 0.75f, origin);
    if (!(r.solid_angle > 1e-4f)) continue;
    double worst_folded = 0.0, worst_paper = 0.0, worst_direction = 0.0;
    for (int j = 0; j < 20; ++j) {
      const float u = unit(rng), v = unit(rng);
      const glm::dvec3 exact = paper_sample(r, u, v);
      worst_folded = std::max(worst_folded, glm::length(glm::dvec3(r.sample(u, v)) - exact));
      vec3 wi;
      float distance = 0.0f;
      r.sample_direction(u, v, wi, distance);
      EXPECT_NEAR(glm::length(wi), 1.0f, 1e-6f);
      worst_direction =
          std::max(worst_direction,
                   glm::length(glm::dvec3(origin) + double{distance} * glm::dvec3(wi) - exact));
      worst_paper =
          std::max(worst_paper, glm::length(glm::dvec3(paper_sample_float(r, u, v)) - exact));
    }
    if (r.solid_angle >= 3e-4f) {  // where the lights use it (light_detail::spherical_usable)
      EXPECT_LE(worst_folded, 5e-4) << "z0 " << r.z0 << " origin y " << origin.y;
      EXPECT_LE(worst_direction, 5e-4) << "z0 " << r.z0 << " origin y " << origin.y;
    }
    if (!r.near_plane) {
      EXPECT_LE(worst_folded, worst_paper + 1e-4) << "z0 " << r.z0;
    }
    near_plane_points += r.near_plane ? 1 : 0;
    sum_folded += worst_folded;
    sum_paper += worst_paper;
    ++points;
  }
  EXPECT_GT(points, 200);
  EXPECT_GT(near_plane_points, 20);
  EXPECT_LE(sum_folded, sum_paper);
}

// Points a few millimetres from a 1 x 1 light's plane, up to 3 m beside it (ratios of
// in-plane distance to height up to 3,000): each sample, and the point sample_direction's
// direction and distance reach, within 1e-5 of the double-precision point, relative to its
// distance.
TEST(SphericalRectangle, PointsNearlyLevelWithTheLightSampleItExactly) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const vec3 corner(-0.5f, -0.5f, 0.0f), x(1.0f, 0.0f, 0.0f), y(0.0f, 1.0f, 0.0f);
  int tested = 0;
  for (int i = 0; i < 200; ++i) {
    const float side = 0.6f + 2.4f * unit(rng), along = -1.0f + 2.0f * unit(rng);
    const float height = 0.001f + 0.02f * unit(rng);
    const vec3 origin = (i % 2 == 0) ? vec3(side, along, height) : vec3(along, -side, -height);
    const SphericalRectangle r =
        SphericalRectangle::make(corner, x, y, glm::cross(x, y), 1.0f, 1.0f, origin);
    if (!(r.solid_angle > 3e-4f)) continue;
    ASSERT_TRUE(r.near_plane) << origin.x << " " << origin.y << " " << origin.z;
    ++tested;
    for (int j = 0; j < 20; ++j) {
      const float u = unit(rng), v = unit(rng);
      const glm::dvec3 exact = paper_sample(r, u, v);
      const double distance = glm::length(exact - glm::dvec3(origin));
      EXPECT_LE(glm::length(glm::dvec3(r.sample(u, v)) - exact), 1e-5 * distance)
          << "origin " << origin.x << " " << origin.y << " " << origin.z << " u " << u << " v "
          << v;
      vec3 wi;
      float sampled_distance = 0.0f;
      r.sample_direction(u, v, wi, sampled_distance);
      const glm::dvec3 reached = glm::dvec3(origin) + double{sampled_distance} * glm::dvec3(wi);
      EXPECT_LE(glm::length(reached - exact), 1e-5 * distance)
          << "origin " << origin.x << " " << origin.y << " " << origin.z << " u " << u << " v "
          << v;
    }
  }
  EXPECT_GT(tested, 100);
}

}  // namespace
}  // namespace tessera
