#pragma once
// Reference ray/shape intersections in quad precision: every hit t > 0, ascending. Each
// shape is written from its definition (an implicit equation per part plus the part's
// bounds), not from the production code, and the polynomial is expanded around a point
// near the shape (found in quad) so that even origins 1e6 sizes away keep ~25 digits.
#include "quad_precision.hpp"
#include "reference_roots.hpp"
#include "tessera/geometry/cone.hpp"
#include "tessera/geometry/cylinder.hpp"
#include "tessera/geometry/disk.hpp"
#include "tessera/geometry/instance.hpp"
#include "tessera/geometry/plane.hpp"
#include "tessera/geometry/quad.hpp"
#include "tessera/geometry/sphere.hpp"
#include "tessera/geometry/sphere_tracing.hpp"
#include "tessera/geometry/torus.hpp"
#include "tessera/geometry/triangle.hpp"

namespace tessera::stress {

struct ReferenceHits {
  int count = 0;
  quad t[8];

  void add(quad value) {
    if (value > 0 && count < 8) t[count++] = value;
  }
  void sort() {
    for (int i = 1; i < count; ++i)
      for (int j = i; j > 0 && t[j - 1] > t[j]; --j) {
        const quad tmp = t[j];
        t[j] = t[j - 1];
        t[j - 1] = tmp;
      }
  }
};

// Parameter interval in which the ray is inside the sphere (center, radius), widened so
// that roots on the sphere itself are inside; empty (lo > hi) when the ray misses it.
struct QInterval {
  quad lo = 1, hi = 0;
};
inline QInterval sphere_interval(const QRay& ray, const QVec& center, quad radius) {
  const QVec f = ray.origin - center;
  const quad a = dot(ray.direction, ray.direction);
  const quad t_mid = -dot(f, ray.direction) / a;
  const QVec closest = f + t_mid * ray.direction;
  const quad padded = radius * quad(1.001);
  const quad h2 = (padded * padded - dot(closest, closest)) / a;
  if (h2 < 0) return {};
  const quad h = qsqrt(h2);
  return {t_mid - h, t_mid + h};
}

// Roots of a polynomial in t given by a callback that fills coefficients for the ray
// origin moved to t_mid (so the coefficients are formed from small numbers).
template <typename Coefficients>
void polynomial_hits(const QRay& ray, const QInterval& interval, int degree,
                     Coefficients&& coefficients, quad* roots, int& count) {
  count = 0;
  if (!(interval.lo <= interval.hi)) return;
  const quad t_mid = (interval.lo + interval.hi) / 2;
  const QRay moved{ray.origin + t_mid * ray.direction, ray.direction};
  quad c[5] = {0, 0, 0, 0, 0};
  coefficients(moved, c);
  quad sigma[4];
  const int n = reference_roots(c, degree, interval.lo - t_mid, interval.hi - t_mid, sigma);
  for (int i = 0; i < n; ++i) roots[count++] = t_mid + sigma[i];
}

inline ReferenceHits reference_hits(const Sphere& s, const QRay& ray) {
  ReferenceHits hits;
  const QVec center(s.center);
  const quad r = s.radius;
  quad roots[4];
  int n;
  polynomial_hits(
      ray, sphere_interval(ray, center, r), 2,
      [&](const QRay& m, quad* c) {
        const QVec f = m.origin - center;
        c[2] = dot(m.direction, m.direction);
        c[1] = 2 * dot(f, m.direction);
        c[0] = dot(f, f) - r * r;
      },
      roots, n);
  for (int i = 0; i < n; ++i) hits.add(roots[i]);
  hits.sort();
  return hits;
}

// Plane n . (x - p) = 0: the root and whether the ray lies in the plane's direction.
inline bool plane_root(const QRay& ray, const QVec& point, const QVec& normal, quad& t) {
  const quad denominator = dot(normal, ray.direction);
  if (denominator == 0) return false;
  t = dot(normal, point - ray.origin) / denominator;
  return true;
}

inline ReferenceHits reference_hits(const Plane& p, const QRay& ray) {
  ReferenceHits hits;
  quad t;
  if (plane_root(ray, QVec(p.point), QVec(p.normal), t)) hits.add(t);
  return hits;
}

inline ReferenceHits reference_hits(const Disk& d, const QRay& ray) {
  ReferenceHits hits;
  const QVec n = normalize(QVec(d.normal));
  quad t;
  if (!plane_root(ray, QVec(d.center), n, t)) return hits;
  const QVec offset = ray.origin + t * ray.direction - QVec(d.center);
  const QVec in_plane = offset - dot(offset, n) * n;
  const quad rho2 = dot(in_plane, in_plane);
  const quad r = d.radius, ri = d.inner_radius;
  if (rho2 <= r * r && rho2 >= ri * ri) hits.add(t);
  return hits;
}

inline ReferenceHits reference_hits(const Quad& q, const QRay& ray) {
  ReferenceHits hits;
  const QVec u(q.u), v(q.v), corner(q.corner);
  const QVec n = cross(u, v);
  quad t;
  if (!plane_root(ray, corner, n, t)) return hits;
  const QVec planar = ray.origin + t * ray.direction - corner;
  const quad nn = dot(n, n);
  const quad s = dot(cross(planar, v), n) / nn;
  const quad r = dot(cross(u, planar), n) / nn;
  if (s >= 0 && s <= 1 && r >= 0 && r <= 1) hits.add(t);
  return hits;
}

// Triangle: the ray's line crosses the triangle when the three signed volumes of the line
// with the edges agree in sign (exact in quad for float inputs up to the products' size).
inline ReferenceHits reference_hits(const Triangle& tri, const QRay& ray) {
  ReferenceHits hits;
  const QVec p0(tri.p0), p1(tri.p1), p2(tri.p2);
  const QVec n = cross(p1 - p0, p2 - p0);
  quad t;
  if (dot(n, n) == 0 || !plane_root(ray, p0, n, t)) return hits;
  const QVec a = p0 - ray.origin, b = p1 - ray.origin, c = p2 - ray.origin;
  const quad w0 = dot(ray.direction, cross(b, c));
  const quad w1 = dot(ray.direction, cross(c, a));
  const quad w2 = dot(ray.direction, cross(a, b));
  const bool inside = (w0 >= 0 && w1 >= 0 && w2 >= 0) || (w0 <= 0 && w1 <= 0 && w2 <= 0);
  if (inside) hits.add(t);
  return hits;
}

// Cylinder and cone share the lateral equation |x_perp|^2 = (r0 + k z)^2 with 0 <= z <= h.
inline void lateral_reference(const QRay& ray, const QVec& base, const QVec& w, quad r0, quad r1,
                              quad h, ReferenceHits& hits) {
  const quad k = (r1 - r0) / h;
  const quad r_max = r0 > r1 ? r0 : r1;
  const QVec middle = base + (h / 2) * w;
  const quad bound = qsqrt(r_max * r_max + h * h / 4);
  quad roots[4];
  int n;
  polynomial_hits(
      ray, sphere_interval(ray, middle, bound), 2,
      [&](const QRay& m, quad* c) {
        const QVec f = m.origin - base;
        const quad fz = dot(f, w), dz = dot(m.direction, w);
        const QVec fp = f - fz * w, dp = m.direction - dz * w;
        const quad radius0 = r0 + k * fz;
        c[2] = dot(dp, dp) - k * k * dz * dz;
        c[1] = 2 * (dot(fp, dp) - k * dz * radius0);
        c[0] = dot(fp, fp) - radius0 * radius0;
      },
      roots, n);
  for (int i = 0; i < n; ++i) {
    const quad z = dot(ray.origin + roots[i] * ray.direction - base, w);
    if (z >= 0 && z <= h) hits.add(roots[i]);
  }
}

inline void cap_reference(const QRay& ray, const QVec& center, const QVec& w, quad radius,
                          ReferenceHits& hits) {
  if (!(radius > 0)) return;
  quad t;
  if (!plane_root(ray, center, w, t)) return;
  const QVec offset = ray.origin + t * ray.direction - center;
  const QVec in_plane = offset - dot(offset, w) * w;
  if (dot(in_plane, in_plane) <= radius * radius) hits.add(t);
}

inline ReferenceHits reference_hits(const Cylinder& c, const QRay& ray) {
  ReferenceHits hits;
  const QVec w = normalize(QVec(c.axis)), base(c.base);
  const quad h = c.height, r = c.radius;
  lateral_reference(ray, base, w, r, r, h, hits);
  if (c.capped) {
    cap_reference(ray, base, w, r, hits);
    cap_reference(ray, base + h * w, w, r, hits);
  }
  hits.sort();
  return hits;
}

inline ReferenceHits reference_hits(const Cone& c, const QRay& ray) {
  ReferenceHits hits;
  const QVec w = normalize(QVec(c.axis)), base(c.base);
  const quad h = c.height;
  lateral_reference(ray, base, w, c.base_radius, c.top_radius, h, hits);
  if (c.capped) {
    cap_reference(ray, base, w, c.base_radius, hits);
    cap_reference(ray, base + h * w, w, c.top_radius, hits);
  }
  hits.sort();
  return hits;
}

// Torus: (|q|^2 + R^2 - r^2)^2 - 4 R^2 (|q|^2 - (q.w)^2) = 0 for q relative to the centre.
// For a spindle torus the roots on the inner lemon (where the tube from the opposite side
// of the axis is the one at distance r) are not on the visible surface.
inline ReferenceHits reference_hits(const Torus& t, const QRay& ray) {
  ReferenceHits hits;
  const QVec w = normalize(QVec(t.axis)), center(t.center);
  const quad R = t.major_radius, r = t.minor_radius;
  quad roots[4];
  int n;
  polynomial_hits(
      ray, sphere_interval(ray, center, R + r), 4,
      [&](const QRay& m, quad* c) {
        const QVec f = m.origin - center;
        const QVec& d = m.direction;
        const quad dd = dot(d, d), fd = dot(f, d), ff = dot(f, f);
        const quad fz = dot(f, w), dz = dot(d, w);
        const quad e = ff + R * R - r * r;
        // |q|^2 = dd s^2 + 2 fd s + ff ; rho^2 = |q|^2 - (q.w)^2
        const quad p2 = dd - dz * dz, p1 = 2 * (fd - fz * dz), p0 = ff - fz * fz;
        c[4] = dd * dd;
        c[3] = 4 * dd * fd;
        c[2] = 4 * fd * fd + 2 * dd * e - 4 * R * R * p2;
        c[1] = 4 * fd * e - 4 * R * R * p1;
        c[0] = e * e - 4 * R * R * p0;
      },
      roots, n);
  for (int i = 0; i < n; ++i) {
    if (r > R) {
      const QVec q = ray.origin + roots[i] * ray.direction - center;
      const quad z = dot(q, w);
      const quad rho = qsqrt(qabs(dot(q, q) - z * z));
      const quad near = (rho - R) * (rho - R) + z * z - r * r;
      const quad far = (rho + R) * (rho + R) + z * z - r * r;
      if (qabs(near) > qabs(far)) continue;
    }
    hits.add(roots[i]);
  }
  hits.sort();
  return hits;
}

// ---- signed-distance primitives, from their surfaces' pieces (the SDF's zero set)

// Real roots of a t^2 + b t + c in quad, each polished by two Newton steps.
inline int quad_quadratic(quad a, quad b, quad c, quad* roots) {
  if (a == 0) {
    if (b == 0) return 0;
    roots[0] = -c / b;
    return 1;
  }
  const quad disc = b * b - 4 * a * c;
  if (disc < 0) return 0;
  const quad q = -(b + (b >= 0 ? qsqrt(disc) : -qsqrt(disc))) / 2;
  int n = 0;
  roots[n++] = q / a;
  if (q != 0) roots[n++] = c / q;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 2; ++k) {
      const quad f = (a * roots[i] + b) * roots[i] + c, df = 2 * a * roots[i] + b;
      if (df != 0) roots[i] -= f / df;
    }
  return n;
}

// Rounded box (rounding 0: a box): 6 face rectangles, 12 quarter cylinders along the
// edges, 8 eighth spheres at the corners, each kept where it is the surface.
inline ReferenceHits reference_hits(const SdfBox& box, const QRay& ray) {
  ReferenceHits hits;
  const QVec o = ray.origin - QVec(box.center);
  const QVec& d = ray.direction;
  const quad r = box.rounding;
  const quad h[3] = {quad(box.half_extent.x), quad(box.half_extent.y), quad(box.half_extent.z)};
  const quad inner[3] = {h[0] - r, h[1] - r, h[2] - r};
  const auto at = [&](quad t, int axis) { return o[axis] + t * d[axis]; };
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) continue;
    for (int side = -1; side <= 1; side += 2) {
      const quad t = (side * h[k] - o[k]) / d[k];
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      if (qabs(at(t, i)) <= inner[i] && qabs(at(t, j)) <= inner[j]) hits.add(t);
    }
  }
  if (r > 0) {
    for (int k = 0; k < 3; ++k) {  // edges along axis k
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      for (int si = -1; si <= 1; si += 2)
        for (int sj = -1; sj <= 1; sj += 2) {
          const quad ci = si * inner[i], cj = sj * inner[j];
          const quad oi = o[i] - ci, oj = o[j] - cj;
          quad roots[2];
          const int n = quad_quadratic(d[i] * d[i] + d[j] * d[j], 2 * (oi * d[i] + oj * d[j]),
                                       oi * oi + oj * oj - r * r, roots);
          for (int m = 0; m < n; ++m) {
            const quad t = roots[m];
            if (qabs(at(t, k)) <= inner[k] && si * at(t, i) >= inner[i] &&
                sj * at(t, j) >= inner[j])
              hits.add(t);
          }
        }
    }
    for (int corner = 0; corner < 8; ++corner) {
      const quad sx = (corner & 1) ? 1 : -1, sy = (corner & 2) ? 1 : -1, sz = (corner & 4) ? 1 : -1;
      const QVec c(sx * inner[0], sy * inner[1], sz * inner[2]);
      const QVec f = o - c;
      quad roots[2];
      const int n = quad_quadratic(dot(d, d), 2 * dot(f, d), dot(f, f) - r * r, roots);
      for (int m = 0; m < n; ++m) {
        const quad t = roots[m];
        if (sx * at(t, 0) >= inner[0] && sy * at(t, 1) >= inner[1] && sz * at(t, 2) >= inner[2])
          hits.add(t);
      }
    }
  }
  hits.sort();
  // A crossing exactly on the seam of two pieces is found by both: keep one.
  int kept = 0;
  for (int i = 0; i < hits.count; ++i)
    if (kept == 0 || hits.t[i] - hits.t[kept - 1] > quad(1e-25) * qabs(hits.t[i]))
      hits.t[kept++] = hits.t[i];
  hits.count = kept;
  return hits;
}

inline ReferenceHits reference_hits(const SdfTorus& t, const QRay& ray) {
  return reference_hits(Torus{t.center, t.axis, t.major_radius, t.minor_radius, 0}, ray);
}

// Capsule: the cylinder between the endpoints and the two hemispheres beyond them.
inline ReferenceHits reference_hits(const SdfCapsule& c, const QRay& ray) {
  ReferenceHits hits;
  const QVec a(c.a), b(c.b);
  const quad length = qsqrt(dot(b - a, b - a));
  const QVec w = (b - a) * (quad(1) / length);
  const quad r = c.radius;
  lateral_reference(ray, a, w, r, r, length, hits);
  for (int end = 0; end < 2; ++end) {
    const QVec center = end == 0 ? a : b;
    const QVec f = ray.origin - center;
    quad roots[2];
    const int n = quad_quadratic(dot(ray.direction, ray.direction), 2 * dot(f, ray.direction),
                                 dot(f, f) - r * r, roots);
    for (int m = 0; m < n; ++m) {
      const quad side = dot(f + roots[m] * ray.direction, w);
      if ((end == 0 && side <= 0) || (end == 1 && side >= 0)) hits.add(roots[m]);
    }
  }
  hits.sort();
  return hits;
}

// Instance: the world ray mapped to object space by the exact (quad) inverse of the
// object-to-world matrix, so the reference sees the transform as specified, not the
// rounded inverse the production code stores.
struct QAffine {
  quad m[3][3];
  QVec translation;
};
inline QAffine exact_inverse(const AffineTransform& t) {
  quad a[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a[r][c] = t.linear[c][r];  // glm is column-major
  const quad det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                   a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                   a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  QAffine inv;
  inv.m[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) / det;
  inv.m[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
  inv.m[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
  inv.m[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) / det;
  inv.m[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
  inv.m[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
  inv.m[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) / det;
  inv.m[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
  inv.m[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
  const QVec tr(t.translation);
  inv.translation = QVec(-(inv.m[0][0] * tr.x + inv.m[0][1] * tr.y + inv.m[0][2] * tr.z),
                         -(inv.m[1][0] * tr.x + inv.m[1][1] * tr.y + inv.m[1][2] * tr.z),
                         -(inv.m[2][0] * tr.x + inv.m[2][1] * tr.y + inv.m[2][2] * tr.z));
  return inv;
}
inline QVec apply_linear(const QAffine& a, const QVec& v) {
  return QVec(a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
              a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
              a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z);
}

template <typename Shape>
ReferenceHits reference_hits(const Instance<Shape>& instance, const QRay& ray) {
  const QAffine inv = exact_inverse(instance.object_to_world);
  const QRay object{apply_linear(inv, ray.origin) + inv.translation,
                    apply_linear(inv, ray.direction)};
  return reference_hits(instance.shape, object);
}

inline QRay to_qray(const Ray& ray) {
  return QRay{QVec(ray.origin), QVec(ray.direction)};
}

}  // namespace tessera::stress
