// Exact orientation, winding numbers on edges and vertices, trimmed faces with holes and
// loops across the seam of periodic surfaces.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "tessera/geometry/instance.hpp"
#include "tessera/geometry/spline_patch_build.hpp"
#include "tessera/geometry/trimmed_face_build.hpp"
#include "tessera/math/orient2d.hpp"

namespace tessera {
namespace {

// Exact sign of the orientation for coordinates that are multiples of 2^-53 below 2^4:
// scaled by 2^53 they are integers below 2^57, whose products fit in 128 bits.
int exact_orientation_sign(const double* a, const double* b, const double* c) {
  const auto scaled = [](double x) { return static_cast<__int128>(std::ldexp(x, 53)); };
  const __int128 det = (scaled(a[0]) - scaled(c[0])) * (scaled(b[1]) - scaled(c[1])) -
                       (scaled(a[1]) - scaled(c[1])) * (scaled(b[0]) - scaled(c[0]));
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

int sign(double x) {
  return x > 0.0 ? 1 : (x < 0.0 ? -1 : 0);
}

// Kettner et al., "Classroom examples of robustness problems in geometric computations":
// p = (0.5 + i u, 0.5 + j u) against the line through (12, 12) and (24, 24), u = 2^-53.
TEST(Orient2d, ExactOnNearCollinearPointsWherePlainDoubleFails) {
  const double u = std::ldexp(1.0, -53);
  const double q[2] = {12.0, 12.0}, r[2] = {24.0, 24.0};
  int plain_wrong = 0, wrong = 0, zero_cases = 0;
  for (int i = 0; i < 256; ++i) {
    for (int j = 0; j < 256; ++j) {
      const double p[2] = {0.5 + i * u, 0.5 + j * u};
      const int exact = exact_orientation_sign(p, q, r);
      zero_cases += exact == 0;
      const double plain = (p[0] - r[0]) * (q[1] - r[1]) - (p[1] - r[1]) * (q[0] - r[0]);
      plain_wrong += sign(plain) != exact;
      wrong += sign(orient2d(p[0], p[1], q[0], q[1], r[0], r[1])) != exact;
      // The argument order only flips the sign.
      wrong += sign(orient2d(q[0], q[1], p[0], p[1], r[0], r[1])) != -exact;
    }
  }
  EXPECT_GT(plain_wrong, 1000);  // the inputs do defeat plain double arithmetic
  EXPECT_GT(zero_cases, 0);      // and some are exactly collinear
  EXPECT_EQ(wrong, 0);
}

TEST(Orient2d, RandomNearCollinearTriplesMatchIntegerArithmetic) {
  std::mt19937_64 rng(1);
  std::uniform_int_distribution<long long> big(-(1LL << 55), 1LL << 55);
  std::uniform_int_distribution<int> small(-4, 4);
  int wrong = 0, filtered_out = 0;
  for (int k = 0; k < 20000; ++k) {
    // a, c random; b = a + 3 (c - a) nudged by a few units: nearly collinear.
    const long long ax = big(rng) / 8, ay = big(rng) / 8, cx = big(rng) / 8, cy = big(rng) / 8;
    const long long bx = ax + 3 * (cx - ax) / 4 + small(rng),
                    by = ay + 3 * (cy - ay) / 4 + small(rng);
    const double a[2] = {std::ldexp(double(ax), -53), std::ldexp(double(ay), -53)};
    const double b[2] = {std::ldexp(double(bx), -53), std::ldexp(double(by), -53)};
    const double c[2] = {std::ldexp(double(cx), -53), std::ldexp(double(cy), -53)};
    const int exact = exact_orientation_sign(a, b, c);
    const double plain = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
    filtered_out += sign(plain) != exact;
    wrong += sign(orient2d(a[0], a[1], b[0], b[1], c[0], c[1])) != exact;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(filtered_out, 0);
}

TrimLoop make_loop(std::vector<dvec2>& pool, const std::vector<dvec2>& points) {
  TrimLoop loop{static_cast<std::uint32_t>(pool.size()), static_cast<std::uint32_t>(points.size()),
                dvec2(1e300), dvec2(-1e300)};
  for (const dvec2& p : points) {
    pool.push_back(p);
    loop.lower = glm::min(loop.lower, p);
    loop.upper = glm::max(loop.upper, p);
  }
  return loop;
}

TEST(Winding, EdgesAndVerticesAreBoundaryConcaveAndOverlappingLoops) {
  std::vector<dvec2> pool;
  pool.reserve(64);
  // An L shape (concave), counter-clockwise.
  const TrimLoop l = make_loop(pool, {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
  const auto side = [&](double x, double y) { return loop_side(pool.data(), l, dvec2(x, y)); };
  EXPECT_EQ(side(0.5, 0.5), LoopSide::kInside);
  EXPECT_EQ(side(1.5, 1.5), LoopSide::kOutside);  // in the notch
  EXPECT_EQ(side(0.5, 1.5), LoopSide::kInside);
  EXPECT_EQ(side(3.0, 0.5), LoopSide::kOutside);
  // Exactly on every vertex and on edge midpoints (including the reflex corner).
  for (const dvec2 v :
       {dvec2{0, 0}, dvec2{2, 0}, dvec2{2, 1}, dvec2{1, 1}, dvec2{1, 2}, dvec2{0, 2}, dvec2{1, 0},
        dvec2{2, 0.5}, dvec2{1.5, 1}, dvec2{1, 1.5}, dvec2{0.5, 2}, dvec2{0, 1}})
    EXPECT_EQ(side(v.x, v.y), LoopSide::kOnBoundary) << v.x << " " << v.y;
  // On the horizontal lines through vertices (the half-open rule counts each once).
  EXPECT_EQ(side(-0.5, 1.0), LoopSide::kOutside);
  EXPECT_EQ(side(0.5, 1.0), LoopSide::kInside);
  EXPECT_EQ(side(1.5, 1.0), LoopSide::kOnBoundary);
  EXPECT_EQ(side(1.5, std::nextafter(1.0, 0.0)), LoopSide::kInside);
  EXPECT_EQ(side(1.5, std::nextafter(1.0, 2.0)), LoopSide::kOutside);
  EXPECT_EQ(side(0.5, std::nextafter(1.0, 2.0)), LoopSide::kInside);
  EXPECT_EQ(side(3.0, 1.0), LoopSide::kOutside);
  EXPECT_EQ(side(-1.0, 2.0), LoopSide::kOutside);
  // A point on the line of an edge but beyond its end is not on the boundary.
  EXPECT_EQ(side(3.0, 0.0), LoopSide::kOutside);
  // One ulp off an edge on either side of a slanted edge.
  const TrimLoop tri = make_loop(pool, {{0, 0}, {3, 1}, {0, 1}});
  const double y = 1.0 / 3.0 * 1.5;  // point (1.5, 0.5) lies on the edge (0,0)-(3,1)
  EXPECT_EQ(loop_side(pool.data(), tri, dvec2(1.5, 0.5)), LoopSide::kOnBoundary);
  EXPECT_EQ(loop_side(pool.data(), tri, dvec2(1.5, std::nextafter(y, 1.0))), LoopSide::kInside);
  EXPECT_EQ(loop_side(pool.data(), tri, dvec2(1.5, std::nextafter(y, 0.0))), LoopSide::kOutside);
  // A loop running twice around (winding 2) is inside by the non-zero rule; clockwise too.
  const TrimLoop twice =
      make_loop(pool, {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}, {1, 0}, {1, 1}, {0, 1}});
  EXPECT_EQ(loop_side(pool.data(), twice, dvec2(0.5, 0.5)), LoopSide::kInside);
  const TrimLoop clockwise = make_loop(pool, {{0, 0}, {0, 1}, {1, 1}, {1, 0}});
  EXPECT_EQ(loop_side(pool.data(), clockwise, dvec2(0.5, 0.5)), LoopSide::kInside);
}

Ray ray(vec3 o, vec3 d) {
  return Ray{o, d, 0.0f, kInfinity};
}

TEST(TrimmedFace, HoleInQuadLetsTheRayThroughAndBoundaryBelongsToTheFace) {
  const Quad quad = Quad::make(vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0), 2);
  TrimPool pool;
  Trimmed<Quad> face;
  ASSERT_EQ(build_trimmed_face(quad,
                               {{{0, 0}, {1, 0}, {1, 1}, {0, 1}},
                                {{0.25, 0.25}, {0.75, 0.25}, {0.75, 0.75}, {0.25, 0.75}}},
                               pool, face),
            "");
  HitRecord hit;
  EXPECT_FALSE(intersect(face, ray(vec3(0.5f, 0.5f, 1.0f), vec3(0, 0, -1)), kInfinity, hit, 0u));
  ASSERT_TRUE(intersect(face, ray(vec3(0.1f, 0.5f, 1.0f), vec3(0, 0, -1)), kInfinity, hit, 0u));
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  EXPECT_EQ(surface_at(face, ray(vec3(0.1f, 0.5f, 1.0f), vec3(0, 0, -1)), hit).material, 2u);
  // Exactly on the hole's edge and corner: part of the (closed) face.
  EXPECT_TRUE(intersect(face, ray(vec3(0.25f, 0.5f, 1.0f), vec3(0, 0, -1)), kInfinity, hit, 0u));
  EXPECT_TRUE(intersect(face, ray(vec3(0.75f, 0.75f, 1.0f), vec3(0, 0, -1)), kInfinity, hit, 0u));
  EXPECT_FALSE(
      intersect(face, ray(vec3(0.2500001f, 0.5f, 1.0f), vec3(0, 0, -1)), kInfinity, hit, 0u));
}

TEST(TrimmedFace, RayThroughAHoleInASphereHitsTheSurfaceBehind) {
  // Sphere uv: v = theta / pi from -y; a polar cap v < 0.1 removed as a hole... done as an
  // outer loop v in [0.1, 1] spanning all u (one band loop through both seam edges).
  const Sphere sphere{vec3(0.0f), 1.0f, 0};
  TrimPool pool;
  Trimmed<Sphere> face;
  ASSERT_EQ(build_trimmed_face(sphere, {{{0, 0.1}, {0.5, 0.1}, {1, 0.1}, {1, 1}, {0.5, 1}, {0, 1}}},
                               pool, face),
            "");
  // Along +y from below: enters at the south pole (v = 0, cut away), leaves at the north
  // pole (v = 1, kept).
  const Ray up = ray(vec3(0.0f, -3.0f, 0.0f), vec3(0, 1, 0));
  HitRecord hit;
  ASSERT_TRUE(intersect(face, up, kInfinity, hit, 0u));
  EXPECT_NEAR(hit.t, 4.0f, 1e-5f);
  HitRecord all[4];
  EXPECT_EQ(intersect_all(face, up, kInfinity, all, 4, 0u), 1);
  // The untrimmed sphere has both.
  EXPECT_EQ(intersect_all(sphere, up, kInfinity, all, 4, 0u), 2);
}

// Cylinder side around z: a window u in [0.9, 1.1] (across the seam at u = 0) and v in
// [0.2, 0.8], given with its points on both sides of the seam.
TEST(TrimmedFace, CylinderWindowAcrossTheSeam) {
  const Cylinder cylinder = Cylinder::make(vec3(0.0f), vec3(0, 0, 1), 1.0f, 1.0f, true, 0);
  TrimPool pool;
  Trimmed<Cylinder> face;
  ASSERT_EQ(
      build_trimmed_face(cylinder, {{{0.9, 0.2}, {0.1, 0.2}, {0.1, 0.8}, {0.9, 0.8}}}, pool, face),
      "");
  int checked = 0;
  for (int k = 0; k < 100; ++k) {
    const double u = k / 100.0 + 0.003;
    // Aim from the axis outwards at the angle whose surface_at u is `u` (checked).
    const double a = 2.0 * 3.14159265358979 * u;
    const AxisFrame frame = AxisFrame::from_axis(vec3(0, 0, 1));
    const dvec3 dir = frame.u * std::cos(a) + frame.v * std::sin(a);
    const Ray r = ray(vec3(0.0f, 0.0f, 0.5f), vec3(dir));
    HitRecord h;
    ASSERT_TRUE(intersect(cylinder, r, kInfinity, h, 0u));
    ASSERT_NEAR(surface_at(cylinder, r, h).uv.x, u, 1e-5);
    const bool expected = u < 0.1 || u > 0.9;
    EXPECT_EQ(intersect(face, r, kInfinity, h, 0u), expected) << "u " << u;
    ++checked;
  }
  EXPECT_EQ(checked, 100);
  // A ray along the axis hits only the caps: never part of the trimmed side.
  HitRecord h;
  EXPECT_FALSE(intersect(face, ray(vec3(0.0f, 0.0f, -2.0f), vec3(0, 0, 1)), kInfinity, h, 0u));
}

TEST(TrimmedFace, SphereHoleAcrossTheSeamAndInsideABand) {
  const Sphere sphere{vec3(0.0f), 1.0f, 0};
  TrimPool pool;
  Trimmed<Sphere> face;
  // Outer: the band v in [0.2, 0.8] all the way round; hole: u in [0.95, 1.05] (across the
  // seam), v in [0.4, 0.6].
  ASSERT_EQ(build_trimmed_face(sphere,
                               {{{0, 0.2}, {0.5, 0.2}, {1, 0.2}, {1, 0.8}, {0.5, 0.8}, {0, 0.8}},
                                {{0.95, 0.4}, {0.05, 0.4}, {0.05, 0.6}, {0.95, 0.6}}},
                               pool, face),
            "");
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int in_hole = 0, in_face = 0;
  for (int k = 0; k < 2000; ++k) {
    const dvec3 d = glm::normalize(dvec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5));
    const Ray r = ray(vec3(0.0f), vec3(d));  // from the centre: one hit
    HitRecord h;
    ASSERT_TRUE(intersect(sphere, r, kInfinity, h, 0u));
    const vec2 uv = surface_at(sphere, r, h).uv;
    // Stay clear of the loops' edges (the float uv would decide those).
    const double du = std::min(std::fabs(uv.x - 0.05), std::fabs(uv.x - 0.95));
    const double dv = std::min({std::fabs(uv.y - 0.2), std::fabs(uv.y - 0.8), std::fabs(uv.y - 0.4),
                                std::fabs(uv.y - 0.6)});
    if (du < 1e-4 || dv < 1e-4) continue;
    const bool hole = (uv.x > 0.95 || uv.x < 0.05) && uv.y > 0.4 && uv.y < 0.6;
    const bool expected = uv.y > 0.2 && uv.y < 0.8 && !hole;
    in_hole += hole;
    in_face += expected;
    EXPECT_EQ(intersect(face, r, kInfinity, h, 0u), expected) << uv.x << " " << uv.y;
  }
  EXPECT_GT(in_hole, 5);
  EXPECT_GT(in_face, 500);
}

TEST(TrimmedFace, TrimmedPatchAndInstance) {
  SplinePatchDescription d;
  d.count_u = d.count_v = 4;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) d.control_points.push_back(dvec3(i, j, 0.0));
  d.knots_u = d.knots_v = {0, 0, 0, 0, 1, 1, 1, 1};
  SplinePatchPool patches;
  SplinePatch patch{};
  ASSERT_EQ(build_spline_patch(d, patches, patch), "");
  TrimPool pool;
  Trimmed<SplinePatch> face;
  // A triangle of the parameter square: x = 3u, y = 3v below the diagonal u + v <= 1.
  ASSERT_EQ(build_trimmed_face(patch, {{{0, 0}, {1, 0}, {0, 1}}}, pool, face), "");
  HitRecord h;
  EXPECT_TRUE(intersect(face, ray(vec3(0.9f, 0.9f, 1.0f), vec3(0, 0, -1)), kInfinity, h, 0u));
  EXPECT_FALSE(intersect(face, ray(vec3(2.1f, 2.1f, 1.0f), vec3(0, 0, -1)), kInfinity, h, 0u));
  static_assert(PreciseIntersectable<Trimmed<SplinePatch>>);
  Instance<Trimmed<SplinePatch>> instance;
  ASSERT_TRUE(Instance<Trimmed<SplinePatch>>::make(
      face, AffineTransform::from_trs(dvec3(10, 0, 0), dvec3(0, 0, 1), 0.0, dvec3(1.0)), instance));
  EXPECT_TRUE(intersect(instance, ray(vec3(10.9f, 0.9f, 1.0f), vec3(0, 0, -1)), kInfinity, h, 0u));
  EXPECT_NEAR(h.t, 1.0f, 1e-6f);
  EXPECT_FALSE(intersect(instance, ray(vec3(12.1f, 2.1f, 1.0f), vec3(0, 0, -1)), kInfinity, h, 0u));
}

// Each remaining analytic surface: a hit is kept exactly when its surface_at uv is in the
// face (uv from the untrimmed surface), including the torus, periodic in u and v.
template <typename Surface>
void check_against_untrimmed(const Surface& surface, const std::vector<std::vector<dvec2>>& loops,
                             const dvec3& center, double radius, int expected_min_in,
                             int expected_min_out) {
  TrimPool pool;
  Trimmed<Surface> face;
  ASSERT_EQ(build_trimmed_face(surface, loops, pool, face), "");
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int in = 0, out = 0;
  for (int k = 0; k < 3000; ++k) {
    const dvec3 o = center + glm::normalize(dvec3(unit(rng), unit(rng), unit(rng))) * 4.0 * radius;
    const dvec3 target = center + dvec3(unit(rng), unit(rng), unit(rng)) * radius;
    const Ray r = ray(vec3(o), vec3(glm::normalize(target - o)));
    HitRecord all[8];
    const int n = intersect_all(surface, r, kInfinity, all, 8, 0u);
    int expected = 0;
    float first = kInfinity;
    for (int i = 0; i < n; ++i) {
      const vec2 uv = surface_at(surface, r, all[i]).uv;
      // Side hits only for cylinders/cones (face_uv refuses caps): all[i].v is the part.
      const bool side = !std::is_same_v<Surface, Cone> || static_cast<int>(all[i].v) == 0;
      if (side && face_contains(face.region, dvec2(uv))) {
        if (expected == 0) first = all[i].t;
        ++expected;
      }
    }
    HitRecord kept[8];
    EXPECT_EQ(intersect_all(face, r, kInfinity, kept, 8, 0u), expected);
    HitRecord hit;
    const bool found = intersect(face, r, kInfinity, hit, 0u);
    EXPECT_EQ(found, expected > 0);
    if (found) {
      EXPECT_EQ(hit.t, first);
    }
    in += expected > 0;
    out += n > 0 && expected == 0;
  }
  EXPECT_GE(in, expected_min_in);
  EXPECT_GE(out, expected_min_out);
}

TEST(TrimmedFace, ConeTorusDiskPlaneAgreeWithTheUntrimmedSurfaceAndTheirUv) {
  check_against_untrimmed(
      Cone::make(vec3(0.0f), vec3(0, 1, 0), 1.0f, 0.2f, 1.5f, true, 0),
      {{{0.8, 0.1}, {0.3, 0.1}, {0.3, 0.9}, {0.8, 0.9}}, {{0.95, 0.4}, {0.05, 0.4}, {0.0, 0.6}}},
      dvec3(0, 0.75, 0), 1.3, 100, 100);
  // Torus: a window across both seams (u near 0 and v near 0 at once).
  check_against_untrimmed(Torus::make(vec3(0.0f), vec3(0, 0, 1), 1.0f, 0.3f, 0),
                          {{{0.9, 0.8}, {0.2, 0.8}, {0.2, 0.2}, {0.9, 0.2}}}, dvec3(0.0), 1.3, 100,
                          100);
  check_against_untrimmed(Disk::make(vec3(0.0f), vec3(0, 0, 1), 1.0f, 0),
                          {{{0.7, 0.2}, {0.4, 0.3}, {0.4, 0.9}, {0.7, 0.9}}}, dvec3(0.0), 1.0, 100,
                          100);
  check_against_untrimmed(Plane::make(vec3(0.0f), vec3(0.2f, 1.0f, 0.1f), 0),
                          {{{-0.5, -0.5}, {0.5, -0.5}, {0.0, 0.5}}}, dvec3(0.0), 1.0, 100, 100);
}

TEST(TrimmedFace, TrimmedPlaneHasFiniteBounds) {
  const Plane plane = Plane::make(vec3(0.0f, 0.0f, 3.0f), vec3(0, 0, 1), 0, 2.0f);
  TrimPool pool;
  Trimmed<Plane> face;
  ASSERT_EQ(build_trimmed_face(plane, {{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}}, pool, face), "");
  const Aabb box = bounds(face);
  EXPECT_NEAR(box.lower.x, -2.0f, 1e-4f);
  EXPECT_NEAR(box.upper.y, 2.0f, 1e-4f);
  EXPECT_NEAR(box.lower.z, 3.0f, 1e-4f);
}

TEST(TrimmedFace, ValidationNamesTheField) {
  TrimPool pool;
  TrimRegion region;
  const UvPeriodicity none{}, periodic_u{true, false};
  EXPECT_NE(build_trim_region({}, none, pool, region, "faces[1]").find("faces[1].loops"),
            std::string::npos);
  EXPECT_NE(build_trim_region({{{0, 0}, {1, 0}}}, none, pool, region)
                .find("trim.loops[0]: must have at least 3 points"),
            std::string::npos);
  EXPECT_NE(
      build_trim_region({{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {NAN, 0}, {1, 1}}}, none, pool, region)
          .find("trim.loops[1][1]: must be finite"),
      std::string::npos);
  EXPECT_NE(build_trim_region({{{0, 0}, {1, 1}, {2, 2}}}, none, pool, region).find("no area"),
            std::string::npos);
  // All the way round a cylinder: a loop that does not close after unwrapping.
  EXPECT_NE(
      build_trim_region({{{0, 0.2}, {0.3, 0.3}, {0.6, 0.2}, {0.9, 0.3}}}, periodic_u, pool, region)
          .find("all the way round"),
      std::string::npos);
  EXPECT_EQ(pool.loops.size(), 0u);  // nothing appended on error
}

}  // namespace
}  // namespace tessera
