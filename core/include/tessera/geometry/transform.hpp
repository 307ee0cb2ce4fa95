#pragma once
#include <cmath>

#include "tessera/math/offset_ray.hpp"
#include "tessera/math/vec.hpp"

namespace tessera {

// Affine map p -> linear * p + translation in double. Instances keep both directions so
// that a ray is taken into object space without inverting anything per ray; double keeps
// an origin far from the instance from losing its position relative to the object.
struct AffineTransform {
  glm::dmat3 linear{1.0};
  dvec3 translation{0.0};

  TESSERA_HD dvec3 point(const dvec3& p) const { return linear * p + translation; }
  TESSERA_HD dvec3 vector(const dvec3& v) const { return linear * v; }

  // Translate * rotate (unit axis, radians) * scale, the usual scene-file order.
  static AffineTransform from_trs(const dvec3& translation, const dvec3& rotation_axis,
                                  double angle, const dvec3& scale) {
    AffineTransform t;
    const dvec3 a =
        glm::length(rotation_axis) > 0.0 ? glm::normalize(rotation_axis) : dvec3(0.0, 0.0, 1.0);
    const double c = std::cos(angle), s = std::sin(angle), k = 1.0 - c;
    // Rodrigues' rotation matrix, column-major (glm): rotation[column][row].
    glm::dmat3 rotation;
    rotation[0] = dvec3(c + a.x * a.x * k, a.y * a.x * k + a.z * s, a.z * a.x * k - a.y * s);
    rotation[1] = dvec3(a.x * a.y * k - a.z * s, c + a.y * a.y * k, a.z * a.y * k + a.x * s);
    rotation[2] = dvec3(a.x * a.z * k + a.y * s, a.y * a.z * k - a.x * s, c + a.z * a.z * k);
    glm::dmat3 scaling(1.0);
    scaling[0][0] = scale.x;
    scaling[1][1] = scale.y;
    scaling[2][2] = scale.z;
    t.linear = rotation * scaling;
    t.translation = translation;
    return t;
  }

  // Inverse; callers must reject singular maps first (determinant() == 0).
  AffineTransform inverse() const {
    AffineTransform inv;
    inv.linear = glm::inverse(linear);
    inv.translation = -(inv.linear * translation);
    return inv;
  }

  TESSERA_HD double determinant() const { return glm::determinant(linear); }

  // The most any coordinate of an error vector can grow through the linear part: the
  // largest row sum of |linear|.
  TESSERA_HD double max_error_gain() const {
    double gain = 0.0;
    for (int row = 0; row < 3; ++row)
      gain = glm::max(
          gain, glm::abs(linear[0][row]) + glm::abs(linear[1][row]) + glm::abs(linear[2][row]));
    return gain;
  }

  // The Frobenius norm of the linear part: a bound on how much it lengthens any vector.
  TESSERA_HD double frobenius_norm() const {
    double norm2 = 0.0;
    for (int c = 0; c < 3; ++c) norm2 += glm::dot(linear[c], linear[c]);
    return std::sqrt(norm2);
  }
};

// SurfaceInteraction::position_error of a world point (rounded to float) mapped from one
// with `object_error` by a transform of max_error_gain() `gain`: the error grown by the
// transform plus the rounding of a point of world's own magnitude. Unknown stays unknown.
TESSERA_HD TESSERA_INLINE float transformed_position_error(float object_error, double gain,
                                                           const vec3& world) {
  if (!(object_error >= 0.0f)) return object_error;
  return static_cast<float>(gain * object_error) +
         position_error_bound(max_component(glm::abs(world)));
}

}  // namespace tessera
