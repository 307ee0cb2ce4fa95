// SIMD traversal kernels of the wide BVH, octree and brute-force triangle tracers.
//
// Included once per instruction set by triangle_kernels_<isa>.cpp, which defines
// TESSERA_KERNEL_NS (the namespace, so each set's instantiations have their own symbols),
// TESSERA_KERNEL_AVX2 (1: eight-wide box tests in one AVX2 instruction; 0: two SSE2
// halves) and TESSERA_KERNEL_AVX512 (1: leaves test three or four triangle blocks at once).
// The AVX2 and AVX-512 files wrap this inclusion in `#pragma GCC target`, so only these
// functions use those sets and the dispatcher can pick them at run time.
//
// Everything here is free of fused multiply-adds on purpose (the kernel files compile with
// -ffp-contract=off, core/CMakeLists.txt, as the AVX-512 target would allow them):
// the watertight triangle test relies on edge functions of shared edges being computed
// with the same roundings, and the results must equal tessera::intersect bit for bit.

namespace tessera::accel_detail::TESSERA_KERNEL_NS {
namespace {

// The walk, the box and triangle tests and the leaf loops are inlined into each query's
// entry point, so the query state (t_max, the best hit) and the ray's constants live in
// registers instead of being reloaded through references after every store.
#define TESSERA_KERNEL_INLINE inline __attribute__((always_inline))

// Per-ray constants, computed once before the walk.
struct PreparedRay {
  // Slab tests: reciprocal direction (infinite for a zero component, see prepare) and, per axis,
  // which bounds row is the near plane and which the far one.
  float origin[3];
  float inv_direction[3];
  std::uint32_t near_row[3];
  std::uint32_t far_row[3];
  float t_min;
  // Watertight triangle test (as WatertightRay): axis permutation and shear.
  std::uint32_t kx, ky, kz;
  float sx, sy, sz;
};

// The slab test of the root's box for prepare (see there).
TESSERA_KERNEL_INLINE bool enters_root_box(__m128 origin, __m128 inv_direction, __m128 direction,
                                           __m128 lower, __m128 upper, const Ray& ray) {
  const __m128 negative = _mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(direction), 31));
  const __m128 near_plane = _mm_or_ps(_mm_and_ps(negative, upper), _mm_andnot_ps(negative, lower));
  const __m128 far_plane = _mm_or_ps(_mm_and_ps(negative, lower), _mm_andnot_ps(negative, upper));
  __m128 t_near =
      _mm_max_ps(_mm_mul_ps(_mm_sub_ps(near_plane, origin), inv_direction), _mm_set1_ps(ray.t_min));
  __m128 t_far =
      _mm_min_ps(_mm_mul_ps(_mm_sub_ps(far_plane, origin),
                            _mm_mul_ps(inv_direction, _mm_set1_ps(wide_node_sse::kFarScale))),
                 _mm_set1_ps(ray.t_max * wide_node_sse::kFarScale));
  t_near = _mm_max_ps(t_near, _mm_shuffle_ps(t_near, t_near, _MM_SHUFFLE(1, 0, 3, 2)));
  t_near = _mm_max_ps(t_near, _mm_shuffle_ps(t_near, t_near, _MM_SHUFFLE(2, 3, 0, 1)));
  t_far = _mm_min_ps(t_far, _mm_shuffle_ps(t_far, t_far, _MM_SHUFFLE(1, 0, 3, 2)));
  t_far = _mm_min_ps(t_far, _mm_shuffle_ps(t_far, t_far, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm_cvtss_f32(t_near) <= _mm_cvtss_f32(t_far);  // false for NaN
}

// Zero direction components give infinite reciprocals (+0.0: +inf, -0.0: -inf), and the
// sign picks the near plane, so -0.0 reads the upper bound first as a tiny negative
// component would. An origin lying exactly on a slab plane of such an axis gives
// 0 * inf = NaN for that plane; the box tests drop NaN operands (see test_node), so the
// ray counts as inside that slab, boundary included, which is what the watertight
// triangle test needs for a ray running along a triangle's edge.
//
// With kRootTest, a ray that misses the root node's box (`root_box`, lower then upper
// corner as x, y, z, z) is rejected here too, before the rest of the set-up: it would find
// every child of the root missed. The set-up (this, and the box and triangle tests'
// broadcasts) is about 190 instructions, over a third of a primary ray's on a mesh that
// half the camera's rays miss. The test is test_node's slab test operation for operation
// (far planes and t_max widened by kFarScale, NaN planes dropped) on a box that holds every
// child's, so it never rejects a ray test_node would let in.
template <bool kRootTest>
TESSERA_KERNEL_INLINE bool prepare(const Ray& ray, const float* root_box, PreparedRay& r) {
  static_assert(sizeof(Ray) == 32 && offsetof(Ray, direction) == 12,
                "origin and direction are read as four lanes each");
  // (ox, oy, oz, oz) and (dx, dy, dz, dz): the z lane repeated where the loads read the
  // next field.
  const __m128 o4 = _mm_loadu_ps(&ray.origin.x);
  const __m128 d4 = _mm_loadu_ps(&ray.direction.x);
  const __m128 origin = _mm_shuffle_ps(o4, o4, _MM_SHUFFLE(2, 2, 1, 0));
  const __m128 direction = _mm_shuffle_ps(d4, d4, _MM_SHUFFLE(2, 2, 1, 0));
  const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 infinity = _mm_set1_ps(kInfinity);
  const __m128 finite = _mm_and_ps(_mm_cmplt_ps(_mm_and_ps(origin, magnitude), infinity),
                                   _mm_cmplt_ps(_mm_and_ps(direction, magnitude), infinity));
  if (_mm_movemask_ps(finite) != 0xF) return false;  // NaN lanes compare false
  if (_mm_movemask_ps(_mm_cmpneq_ps(direction, _mm_setzero_ps())) == 0) return false;
  if (!(ray.t_min <= ray.t_max)) return false;  // also rejects NaN limits
  const __m128 inv_direction = _mm_div_ps(_mm_set1_ps(1.0f), direction);
  if constexpr (kRootTest) {
    const __m128 lower = _mm_load_ps(root_box), upper = _mm_load_ps(root_box + 4);
    // An origin inside the box needs no slab test (bounce and shadow rays start on the
    // geometry): rejecting fewer rays than the slab test would is always safe.
    const bool inside = _mm_movemask_ps(_mm_and_ps(_mm_cmple_ps(lower, origin),
                                                   _mm_cmple_ps(origin, upper))) == 0xF;
    if (!inside && !enters_root_box(origin, inv_direction, direction, lower, upper, ray))
      return false;
  }
  alignas(16) float inverse[4];
  _mm_store_ps(inverse, inv_direction);
  const auto negative_axes = static_cast<std::uint32_t>(_mm_movemask_ps(direction));
  const float d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
  for (std::uint32_t axis = 0; axis < 3; ++axis) {
    r.origin[axis] = ray.origin[static_cast<int>(axis)];
    r.inv_direction[axis] = inverse[axis];
    const std::uint32_t negative = (negative_axes >> axis) & 1U;  // the sign bit, as signbit
    r.near_row[axis] = 2 * axis + negative;
    r.far_row[axis] = 2 * axis + 1 - negative;
  }
  r.t_min = ray.t_min;
  const float ax = std::fabs(d[0]), ay = std::fabs(d[1]), az = std::fabs(d[2]);
  r.kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  r.kx = r.kz + 1 == 3 ? 0 : r.kz + 1;
  r.ky = r.kx + 1 == 3 ? 0 : r.kx + 1;
  if (d[r.kz] < 0.0f) std::swap(r.kx, r.ky);  // keep the winding
  r.sx = d[r.kx] / d[r.kz];
  r.sy = d[r.ky] / d[r.kz];
  r.sz = inverse[r.kz];  // 1 / d[kz], the same division
  return true;
}

// ---- Box tests -------------------------------------------------------------------------

// The far end of each box interval is widened by two ulps (accel/wide_node_sse.hpp says why).
using wide_node_sse::kFarScale;

#if TESSERA_KERNEL_AVX2
struct BoxRay {
  __m256 origin[3], inv_direction[3], inv_direction_far[3], t_min;
  explicit BoxRay(const PreparedRay& r) {
    for (int axis = 0; axis < 3; ++axis) {
      origin[axis] = _mm256_set1_ps(r.origin[axis]);
      inv_direction[axis] = _mm256_set1_ps(r.inv_direction[axis]);
      inv_direction_far[axis] = _mm256_set1_ps(r.inv_direction[axis] * kFarScale);
    }
    t_min = _mm256_set1_ps(r.t_min);
  }
};

// Returns the mask of children whose box the ray enters within [t_min, t_max]; `entry`
// receives the bits of their entry distances, clamped to >= +0. `far_limit` is
// t_max * kFarScale, which the walk forms only when t_max changes.
TESSERA_KERNEL_INLINE std::uint32_t test_node(const WideBvhNode& node, const PreparedRay& r,
                                              const BoxRay& b, float /*t_max*/, float far_limit,
                                              std::uint32_t* entry) {
  const auto slab = [&](std::uint32_t row, int axis, const __m256* inv) {
    return _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[row]), b.origin[axis]),
                         inv[axis]);
  };
  const __m256 near_x = slab(r.near_row[0], 0, b.inv_direction),
               near_y = slab(r.near_row[1], 1, b.inv_direction),
               near_z = slab(r.near_row[2], 2, b.inv_direction);
  const __m256 far_x = slab(r.far_row[0], 0, b.inv_direction_far),
               far_y = slab(r.far_row[1], 1, b.inv_direction_far),
               far_z = slab(r.far_row[2], 2, b.inv_direction_far);
  // max/min return their second operand when either is NaN: the plane distances go first
  // and the accumulated interval second, so a NaN plane leaves the interval unchanged.
  const __m256 t_near =
      _mm256_max_ps(near_x, _mm256_max_ps(near_y, _mm256_max_ps(near_z, b.t_min)));
  const __m256 t_far =
      _mm256_min_ps(far_x, _mm256_min_ps(far_y, _mm256_min_ps(far_z, _mm256_set1_ps(far_limit))));
  // Entry distances clamped to +0 (max returns its second operand for -0 and NaN), so their
  // bits order like their values: the stack keys need no branch (see stack_key).
  _mm256_store_ps(reinterpret_cast<float*>(entry), _mm256_max_ps(t_near, _mm256_setzero_ps()));
  return static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_cmp_ps(t_near, t_far, _CMP_LE_OQ)));
}
#else
// The SSE2 node test is the one the shape BVH's walk uses too (accel/wide_node_sse.hpp).
struct BoxRay : wide_node_sse::BoxRay {
  explicit BoxRay(const PreparedRay& r)
      : wide_node_sse::BoxRay(r.origin, r.inv_direction, r.near_row, r.far_row, r.t_min) {}
};

TESSERA_KERNEL_INLINE std::uint32_t test_node(const WideBvhNode& node, const PreparedRay&,
                                              const BoxRay& b, float t_max, float /*far_limit*/,
                                              std::uint32_t* entry) {
  return wide_node_sse::test_node(node, b, t_max, entry);
}
#endif

// ---- Triangle blocks -------------------------------------------------------------------

// Lane arrays of each vector width, for the rare scalar pass below.
inline void store_lanes(float* to, __m128 v) {
  _mm_store_ps(to, v);
}
inline __m128 load_lanes(const float* from, __m128) {
  return _mm_load_ps(from);
}
#if TESSERA_KERNEL_AVX2
inline void store_lanes(float* to, __m256 v) {
  _mm256_store_ps(to, v);
}
inline __m256 load_lanes(const float* from, __m256) {
  return _mm256_load_ps(from);
}
#endif
#if TESSERA_KERNEL_AVX512
inline void store_lanes(float* to, __m512 v) {
  _mm512_store_ps(to, v);
}
inline __m512 load_lanes(const float* from, __m512) {
  return _mm512_load_ps(from);
}
#endif

// An edge function of exactly zero is recomputed in double, so the sign decision on a
// shared edge or vertex is exact (rare: a scalar pass over the lanes in `zero_lanes`). The
// same for the four-, eight- and sixteen-lane tests.
template <typename V>
TESSERA_KERNEL_INLINE void exact_zero_edges(std::uint32_t zero_lanes, V& u, V& w1, V& w2, V ax,
                                            V ay, V bx, V by, V cx, V cy) {
  constexpr int kLanes = static_cast<int>(sizeof(V) / sizeof(float));
  alignas(64) float u_[kLanes], w1_[kLanes], w2_[kLanes], ax_[kLanes], ay_[kLanes], bx_[kLanes],
      by_[kLanes], cx_[kLanes], cy_[kLanes];
  store_lanes(u_, u);
  store_lanes(w1_, w1);
  store_lanes(w2_, w2);
  store_lanes(ax_, ax);
  store_lanes(ay_, ay);
  store_lanes(bx_, bx);
  store_lanes(by_, by);
  store_lanes(cx_, cx);
  store_lanes(cy_, cy);
  for (int lane = 0; lane < kLanes; ++lane) {
    if (!(zero_lanes & (1U << lane))) continue;
    u_[lane] = static_cast<float>(static_cast<double>(cx_[lane]) * by_[lane] -
                                  static_cast<double>(cy_[lane]) * bx_[lane]);
    w1_[lane] = static_cast<float>(static_cast<double>(ax_[lane]) * cy_[lane] -
                                   static_cast<double>(ay_[lane]) * cx_[lane]);
    w2_[lane] = static_cast<float>(static_cast<double>(bx_[lane]) * ay_[lane] -
                                   static_cast<double>(by_[lane]) * ax_[lane]);
  }
  u = load_lanes(u_, u);
  w1 = load_lanes(w1_, w1);
  w2 = load_lanes(w2_, w2);
}

// The ray's constants for the triangle tests, broadcast once per ray. With AVX2 they are
// eight lanes wide for intersect_pair, and intersect_block reads their lower halves: a
// second, four-lane copy cost seven more broadcasts and stores per ray, and one formed at
// each leaf seven per leaf.
#if TESSERA_KERNEL_AVX2
using RayLanes = __m256;
TESSERA_KERNEL_INLINE __m128 low_lanes(__m256 v) {
  return _mm256_castps256_ps128(v);
}
TESSERA_KERNEL_INLINE __m256 broadcast_lanes(float x) {
  return _mm256_set1_ps(x);
}
#else
using RayLanes = __m128;
TESSERA_KERNEL_INLINE __m128 low_lanes(__m128 v) {
  return v;
}
TESSERA_KERNEL_INLINE __m128 broadcast_lanes(float x) {
  return _mm_set1_ps(x);
}
#endif

struct TriangleRay {
  RayLanes origin_x, origin_y, origin_z;  // origin in the permuted frame
  RayLanes sx, sy, sz, t_min;
  // Float offsets of the permuted axes in a vertex row, pointer-sized: with 32-bit offsets
  // the sums 12 + row_x, 24 + row_x, ... were formed in registers at every leaf (they may
  // wrap), where pointer-sized ones fold into the loads' addresses.
  std::size_t row_x, row_y, row_z;
  explicit TriangleRay(const PreparedRay& r)
      : origin_x(broadcast_lanes(r.origin[r.kx])),
        origin_y(broadcast_lanes(r.origin[r.ky])),
        origin_z(broadcast_lanes(r.origin[r.kz])),
        sx(broadcast_lanes(r.sx)),
        sy(broadcast_lanes(r.sy)),
        sz(broadcast_lanes(r.sz)),
        t_min(broadcast_lanes(r.t_min)),
        row_x(4 * r.kx),
        row_y(4 * r.ky),
        row_z(4 * r.kz) {}
};

// Lanes of one block the ray hits in (t_min, t_max), with t and barycentrics per lane.
struct BlockHits {
  std::uint32_t mask;
  __m128 valid, t, b1, b2;
};

// The watertight test of tessera::intersect on four triangles at once, operation for
// operation, so each lane's result is bit-identical to the scalar one.
TESSERA_KERNEL_INLINE std::uint32_t intersect_block(const TriangleBlock4& block,
                                                    const TriangleRay& r, float t_max,
                                                    BlockHits& out) {
  const float* v = &block.vertices[0][0][0];
  const __m128 origin_x = low_lanes(r.origin_x), origin_y = low_lanes(r.origin_y),
               origin_z = low_lanes(r.origin_z), sx = low_lanes(r.sx), sy = low_lanes(r.sy),
               sz = low_lanes(r.sz);
  // Vertex rows are 12 floats apart ([vertex][axis][lane]).
  const __m128 a_x = _mm_sub_ps(_mm_load_ps(v + r.row_x), origin_x);
  const __m128 a_y = _mm_sub_ps(_mm_load_ps(v + r.row_y), origin_y);
  const __m128 a_z = _mm_sub_ps(_mm_load_ps(v + r.row_z), origin_z);
  const __m128 b_x = _mm_sub_ps(_mm_load_ps(v + 12 + r.row_x), origin_x);
  const __m128 b_y = _mm_sub_ps(_mm_load_ps(v + 12 + r.row_y), origin_y);
  const __m128 b_z = _mm_sub_ps(_mm_load_ps(v + 12 + r.row_z), origin_z);
  const __m128 c_x = _mm_sub_ps(_mm_load_ps(v + 24 + r.row_x), origin_x);
  const __m128 c_y = _mm_sub_ps(_mm_load_ps(v + 24 + r.row_y), origin_y);
  const __m128 c_z = _mm_sub_ps(_mm_load_ps(v + 24 + r.row_z), origin_z);
  const __m128 ax = _mm_sub_ps(a_x, _mm_mul_ps(sx, a_z));
  const __m128 ay = _mm_sub_ps(a_y, _mm_mul_ps(sy, a_z));
  const __m128 bx = _mm_sub_ps(b_x, _mm_mul_ps(sx, b_z));
  const __m128 by = _mm_sub_ps(b_y, _mm_mul_ps(sy, b_z));
  const __m128 cx = _mm_sub_ps(c_x, _mm_mul_ps(sx, c_z));
  const __m128 cy = _mm_sub_ps(c_y, _mm_mul_ps(sy, c_z));
  __m128 u = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
  __m128 w1 = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
  __m128 w2 = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
  const __m128 zero = _mm_setzero_ps();

  // Lanes with an edge function of exactly zero: recomputed in double (exact_zero_edges).
  const int zero_lanes = _mm_movemask_ps(
      _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(u, zero), _mm_cmpeq_ps(w1, zero)), _mm_cmpeq_ps(w2, zero)));
  if (zero_lanes != 0) [[unlikely]]
    exact_zero_edges(static_cast<std::uint32_t>(zero_lanes), u, w1, w2, ax, ay, bx, by, cx, cy);

  const __m128 negative =
      _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, zero), _mm_cmplt_ps(w1, zero)), _mm_cmplt_ps(w2, zero));
  const __m128 positive =
      _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, zero), _mm_cmpgt_ps(w1, zero)), _mm_cmpgt_ps(w2, zero));
  const __m128 det = _mm_add_ps(_mm_add_ps(u, w1), w2);
  // Mixed signs: the ray passes outside. NaN lanes (padding) fail the t test below.
  __m128 valid = _mm_andnot_ps(_mm_and_ps(negative, positive), _mm_cmpneq_ps(det, zero));
  if (_mm_movemask_ps(valid) == 0) return 0;

  const __m128 t_scaled = _mm_add_ps(
      _mm_add_ps(_mm_mul_ps(u, _mm_mul_ps(sz, a_z)), _mm_mul_ps(w1, _mm_mul_ps(sz, b_z))),
      _mm_mul_ps(w2, _mm_mul_ps(sz, c_z)));
  const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
  const __m128 t = _mm_mul_ps(t_scaled, inv_det);
  valid = _mm_and_ps(
      valid, _mm_and_ps(_mm_cmpgt_ps(t, low_lanes(r.t_min)), _mm_cmplt_ps(t, _mm_set1_ps(t_max))));
  out.mask = static_cast<std::uint32_t>(_mm_movemask_ps(valid));
  out.valid = valid;
  out.t = t;
  out.b1 = _mm_mul_ps(w1, inv_det);
  out.b2 = _mm_mul_ps(w2, inv_det);
  return out.mask;
}

#if TESSERA_KERNEL_AVX2
// Two blocks at once on eight AVX2 lanes (lanes 0-3 the first block, 4-7 the second):
// the same operations as intersect_block, so each lane's result is the same bit for bit.

struct PairHits {
  std::uint32_t mask;
  __m256 valid, t, b1, b2;
};

TESSERA_KERNEL_INLINE std::uint32_t intersect_pair(const TriangleBlock4& first,
                                                   const TriangleBlock4& second,
                                                   const TriangleRay& r, float t_max,
                                                   PairHits& out) {
  const float* v0 = &first.vertices[0][0][0];
  const float* v1 = &second.vertices[0][0][0];
  const auto row = [&](std::size_t offset) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(v0 + offset)),
                                _mm_load_ps(v1 + offset), 1);
  };
  const __m256 a_x = _mm256_sub_ps(row(r.row_x), r.origin_x);
  const __m256 a_y = _mm256_sub_ps(row(r.row_y), r.origin_y);
  const __m256 a_z = _mm256_sub_ps(row(r.row_z), r.origin_z);
  const __m256 b_x = _mm256_sub_ps(row(12 + r.row_x), r.origin_x);
  const __m256 b_y = _mm256_sub_ps(row(12 + r.row_y), r.origin_y);
  const __m256 b_z = _mm256_sub_ps(row(12 + r.row_z), r.origin_z);
  const __m256 c_x = _mm256_sub_ps(row(24 + r.row_x), r.origin_x);
  const __m256 c_y = _mm256_sub_ps(row(24 + r.row_y), r.origin_y);
  const __m256 c_z = _mm256_sub_ps(row(24 + r.row_z), r.origin_z);
  const __m256 ax = _mm256_sub_ps(a_x, _mm256_mul_ps(r.sx, a_z));
  const __m256 ay = _mm256_sub_ps(a_y, _mm256_mul_ps(r.sy, a_z));
  const __m256 bx = _mm256_sub_ps(b_x, _mm256_mul_ps(r.sx, b_z));
  const __m256 by = _mm256_sub_ps(b_y, _mm256_mul_ps(r.sy, b_z));
  const __m256 cx = _mm256_sub_ps(c_x, _mm256_mul_ps(r.sx, c_z));
  const __m256 cy = _mm256_sub_ps(c_y, _mm256_mul_ps(r.sy, c_z));
  __m256 u = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
  __m256 w1 = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
  __m256 w2 = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
  const __m256 zero = _mm256_setzero_ps();
  const int zero_lanes = _mm256_movemask_ps(_mm256_or_ps(
      _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_EQ_OQ), _mm256_cmp_ps(w1, zero, _CMP_EQ_OQ)),
      _mm256_cmp_ps(w2, zero, _CMP_EQ_OQ)));
  if (zero_lanes != 0) [[unlikely]]
    exact_zero_edges(static_cast<std::uint32_t>(zero_lanes), u, w1, w2, ax, ay, bx, by, cx, cy);
  const __m256 negative = _mm256_or_ps(
      _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_LT_OQ), _mm256_cmp_ps(w1, zero, _CMP_LT_OQ)),
      _mm256_cmp_ps(w2, zero, _CMP_LT_OQ));
  const __m256 positive = _mm256_or_ps(
      _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_GT_OQ), _mm256_cmp_ps(w1, zero, _CMP_GT_OQ)),
      _mm256_cmp_ps(w2, zero, _CMP_GT_OQ));
  const __m256 det = _mm256_add_ps(_mm256_add_ps(u, w1), w2);
  __m256 valid =
      _mm256_andnot_ps(_mm256_and_ps(negative, positive), _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ));
  if (_mm256_movemask_ps(valid) == 0) return 0;
  const __m256 t_scaled = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(u, _mm256_mul_ps(r.sz, a_z)),
                                                      _mm256_mul_ps(w1, _mm256_mul_ps(r.sz, b_z))),
                                        _mm256_mul_ps(w2, _mm256_mul_ps(r.sz, c_z)));
  const __m256 inv_det = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
  const __m256 t = _mm256_mul_ps(t_scaled, inv_det);
  valid = _mm256_and_ps(valid, _mm256_and_ps(_mm256_cmp_ps(t, r.t_min, _CMP_GT_OQ),
                                             _mm256_cmp_ps(t, _mm256_set1_ps(t_max), _CMP_LT_OQ)));
  out.mask = static_cast<std::uint32_t>(_mm256_movemask_ps(valid));
  out.valid = valid;
  out.t = t;
  out.b1 = _mm256_mul_ps(w1, inv_det);
  out.b2 = _mm256_mul_ps(w2, inv_det);
  return out.mask;
}

inline float lane_of(__m256 v, std::uint32_t lane) {
  alignas(32) float values[8];
  _mm256_store_ps(values, v);
  return values[lane];
}
#endif

#if TESSERA_KERNEL_AVX512
// Three or four blocks at once on sixteen AVX-512 lanes (block k in lanes 4k..4k+3): the same
// operations as intersect_block, so each lane's result is the same bit for bit. With three
// blocks the third is loaded twice and its second copy's lanes are masked off.
struct QuadRay {
  __m512 origin_x, origin_y, origin_z, sx, sy, sz, t_min;
  std::size_t row_x, row_y, row_z;  // as TriangleRay's
  explicit QuadRay(const TriangleRay& r)
      : origin_x(_mm512_broadcastss_ps(low_lanes(r.origin_x))),
        origin_y(_mm512_broadcastss_ps(low_lanes(r.origin_y))),
        origin_z(_mm512_broadcastss_ps(low_lanes(r.origin_z))),
        sx(_mm512_broadcastss_ps(low_lanes(r.sx))),
        sy(_mm512_broadcastss_ps(low_lanes(r.sy))),
        sz(_mm512_broadcastss_ps(low_lanes(r.sz))),
        t_min(_mm512_broadcastss_ps(low_lanes(r.t_min))),
        row_x(r.row_x),
        row_y(r.row_y),
        row_z(r.row_z) {}
};

struct QuadHits {
  std::uint32_t mask;
  __m512 t, b1, b2;
};

TESSERA_KERNEL_INLINE std::uint32_t intersect_quad(const TriangleBlock4* blocks, bool four,
                                                   const QuadRay& r, float t_max, QuadHits& out) {
  const float* v0 = &blocks[0].vertices[0][0][0];
  const float* v1 = &blocks[1].vertices[0][0][0];
  const float* v2 = &blocks[2].vertices[0][0][0];
  const float* v3 = four ? &blocks[3].vertices[0][0][0] : v2;
  const auto row = [&](std::size_t offset) {
    __m512 v = _mm512_castps128_ps512(_mm_load_ps(v0 + offset));
    v = _mm512_insertf32x4(v, _mm_load_ps(v1 + offset), 1);
    v = _mm512_insertf32x4(v, _mm_load_ps(v2 + offset), 2);
    return _mm512_insertf32x4(v, _mm_load_ps(v3 + offset), 3);
  };
  const __m512 a_x = _mm512_sub_ps(row(r.row_x), r.origin_x);
  const __m512 a_y = _mm512_sub_ps(row(r.row_y), r.origin_y);
  const __m512 a_z = _mm512_sub_ps(row(r.row_z), r.origin_z);
  const __m512 b_x = _mm512_sub_ps(row(12 + r.row_x), r.origin_x);
  const __m512 b_y = _mm512_sub_ps(row(12 + r.row_y), r.origin_y);
  const __m512 b_z = _mm512_sub_ps(row(12 + r.row_z), r.origin_z);
  const __m512 c_x = _mm512_sub_ps(row(24 + r.row_x), r.origin_x);
  const __m512 c_y = _mm512_sub_ps(row(24 + r.row_y), r.origin_y);
  const __m512 c_z = _mm512_sub_ps(row(24 + r.row_z), r.origin_z);
  const __m512 ax = _mm512_sub_ps(a_x, _mm512_mul_ps(r.sx, a_z));
  const __m512 ay = _mm512_sub_ps(a_y, _mm512_mul_ps(r.sy, a_z));
  const __m512 bx = _mm512_sub_ps(b_x, _mm512_mul_ps(r.sx, b_z));
  const __m512 by = _mm512_sub_ps(b_y, _mm512_mul_ps(r.sy, b_z));
  const __m512 cx = _mm512_sub_ps(c_x, _mm512_mul_ps(r.sx, c_z));
  const __m512 cy = _mm512_sub_ps(c_y, _mm512_mul_ps(r.sy, c_z));
  __m512 u = _mm512_sub_ps(_mm512_mul_ps(cx, by), _mm512_mul_ps(cy, bx));
  __m512 w1 = _mm512_sub_ps(_mm512_mul_ps(ax, cy), _mm512_mul_ps(ay, cx));
  __m512 w2 = _mm512_sub_ps(_mm512_mul_ps(bx, ay), _mm512_mul_ps(by, ax));
  const __m512 zero = _mm512_setzero_ps();
  const __mmask16 zero_lanes = _mm512_cmp_ps_mask(u, zero, _CMP_EQ_OQ) |
                               _mm512_cmp_ps_mask(w1, zero, _CMP_EQ_OQ) |
                               _mm512_cmp_ps_mask(w2, zero, _CMP_EQ_OQ);
  if (zero_lanes != 0) [[unlikely]]
    exact_zero_edges(static_cast<std::uint32_t>(zero_lanes), u, w1, w2, ax, ay, bx, by, cx, cy);
  const __mmask16 negative = _mm512_cmp_ps_mask(u, zero, _CMP_LT_OQ) |
                             _mm512_cmp_ps_mask(w1, zero, _CMP_LT_OQ) |
                             _mm512_cmp_ps_mask(w2, zero, _CMP_LT_OQ);
  const __mmask16 positive = _mm512_cmp_ps_mask(u, zero, _CMP_GT_OQ) |
                             _mm512_cmp_ps_mask(w1, zero, _CMP_GT_OQ) |
                             _mm512_cmp_ps_mask(w2, zero, _CMP_GT_OQ);
  const __m512 det = _mm512_add_ps(_mm512_add_ps(u, w1), w2);
  // Mixed signs: the ray passes outside. NaN lanes (padding) fail the t test below.
  __mmask16 valid = static_cast<__mmask16>(~(negative & positive)) &
                    _mm512_cmp_ps_mask(det, zero, _CMP_NEQ_UQ) &
                    static_cast<__mmask16>(four ? 0xFFFF : 0x0FFF);
  if (valid == 0) return 0;
  const __m512 t_scaled = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(u, _mm512_mul_ps(r.sz, a_z)),
                                                      _mm512_mul_ps(w1, _mm512_mul_ps(r.sz, b_z))),
                                        _mm512_mul_ps(w2, _mm512_mul_ps(r.sz, c_z)));
  const __m512 inv_det = _mm512_div_ps(_mm512_set1_ps(1.0f), det);
  const __m512 t = _mm512_mul_ps(t_scaled, inv_det);
  valid &= _mm512_cmp_ps_mask(t, r.t_min, _CMP_GT_OQ) &
           _mm512_cmp_ps_mask(t, _mm512_set1_ps(t_max), _CMP_LT_OQ);
  out.mask = valid;
  out.t = t;
  out.b1 = _mm512_mul_ps(w1, inv_det);
  out.b2 = _mm512_mul_ps(w2, inv_det);
  return out.mask;
}

inline float lane_of(__m512 v, std::uint32_t lane) {
  alignas(64) float values[16];
  _mm512_store_ps(values, v);
  return values[lane];
}
#endif

inline float lane_of(__m128 v, std::uint32_t lane) {
  alignas(16) float values[4];
  _mm_store_ps(values, v);
  return values[lane];
}

// ---- Queries ---------------------------------------------------------------------------

struct ClosestQuery {
  static constexpr bool kOrdered = true;  // visit near children first, so t_max shrinks early
  float t_max;
  HitRecord best{};
  bool found = false;

  // Returns true to end the traversal.
  TESSERA_KERNEL_INLINE bool leaf(const TriangleBlock4* blocks, std::uint32_t first,
                                  std::uint32_t count, const TriangleRay& r) {
    std::uint32_t b = first;
#if TESSERA_KERNEL_AVX512
    if (count >= 3) {
      const QuadRay quad_ray(r);
      for (; b + 2 < first + count; b += 4) {
        const bool four = b + 3 < first + count;
        QuadHits hits;
        if (intersect_quad(blocks + b, four, quad_ray, t_max, hits) == 0) continue;
        // Nearest lane; on equal t the lowest, the block tested first, as in sequence.
        const __m512 masked = _mm512_mask_blend_ps(static_cast<__mmask16>(hits.mask),
                                                   _mm512_set1_ps(kInfinity), hits.t);
        const float nearest_t = _mm512_reduce_min_ps(masked);
        const auto nearest = static_cast<std::uint32_t>(_mm512_cmp_ps_mask(
                                 masked, _mm512_set1_ps(nearest_t), _CMP_EQ_OQ)) &
                             hits.mask;
        const auto lane = static_cast<std::uint32_t>(__builtin_ctz(nearest));
        t_max = lane_of(hits.t, lane);
        best = HitRecord{t_max, lane_of(hits.b1, lane), lane_of(hits.b2, lane),
                         blocks[b + lane / 4].ids[lane % 4]};
        found = true;
      }
      if (b > first + count) b = first + count;  // three were left: all tested
    }
#endif
#if TESSERA_KERNEL_AVX2
    if (b + 1 < first + count) {
      for (; b + 1 < first + count; b += 2) {
        PairHits hits;
        if (intersect_pair(blocks[b], blocks[b + 1], r, t_max, hits) == 0) continue;
        const __m256 masked = _mm256_blendv_ps(_mm256_set1_ps(kInfinity), hits.t, hits.valid);
        __m256 m = _mm256_min_ps(masked, _mm256_permute_ps(masked, 0xB1));
        m = _mm256_min_ps(m, _mm256_permute_ps(m, 0x4E));
        m = _mm256_min_ps(m, _mm256_permute2f128_ps(m, m, 0x01));
        const auto nearest =
            static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_cmp_ps(masked, m, _CMP_EQ_OQ))) &
            hits.mask;
        const auto lane = static_cast<std::uint32_t>(__builtin_ctz(nearest));
        t_max = lane_of(hits.t, lane);
        best = HitRecord{t_max, lane_of(hits.b1, lane), lane_of(hits.b2, lane),
                         blocks[b + lane / 4].ids[lane % 4]};
        found = true;
      }
    }
#endif
    for (; b < first + count; ++b) {
      BlockHits hits;
      if (intersect_block(blocks[b], r, t_max, hits) == 0) continue;
      // Nearest lane; on equal t the lowest lane, so the choice is deterministic.
      const __m128 masked = _mm_or_ps(_mm_and_ps(hits.valid, hits.t),
                                      _mm_andnot_ps(hits.valid, _mm_set1_ps(kInfinity)));
      __m128 m = _mm_min_ps(masked, _mm_shuffle_ps(masked, masked, _MM_SHUFFLE(2, 3, 0, 1)));
      m = _mm_min_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
      const auto nearest =
          static_cast<std::uint32_t>(_mm_movemask_ps(_mm_cmpeq_ps(masked, m))) & hits.mask;
      const auto lane = static_cast<std::uint32_t>(__builtin_ctz(nearest));
      t_max = lane_of(hits.t, lane);
      best = HitRecord{t_max, lane_of(hits.b1, lane), lane_of(hits.b2, lane), blocks[b].ids[lane]};
      found = true;
    }
    return false;
  }
};

struct AnyQuery {
  static constexpr bool kOrdered = false;  // any hit ends the walk: order does not matter
  float t_max;
  bool found = false;

  TESSERA_KERNEL_INLINE bool leaf(const TriangleBlock4* blocks, std::uint32_t first,
                                  std::uint32_t count, const TriangleRay& r) {
    std::uint32_t b = first;
#if TESSERA_KERNEL_AVX512
    if (count >= 3) {
      const QuadRay quad_ray(r);
      for (; b + 2 < first + count; b += 4) {
        QuadHits hits;
        if (intersect_quad(blocks + b, b + 3 < first + count, quad_ray, t_max, hits) != 0) {
          found = true;
          return true;
        }
      }
      if (b > first + count) b = first + count;
    }
#endif
#if TESSERA_KERNEL_AVX2
    if (b + 1 < first + count) {
      for (; b + 1 < first + count; b += 2) {
        PairHits hits;
        if (intersect_pair(blocks[b], blocks[b + 1], r, t_max, hits) != 0) {
          found = true;
          return true;
        }
      }
    }
#endif
    for (; b < first + count; ++b) {
      BlockHits hits;
      if (intersect_block(blocks[b], r, t_max, hits) != 0) {
        found = true;
        return true;
      }
    }
    return false;
  }
};

// Keeps the `capacity` nearest hits sorted by t; once full, the farthest kept hit bounds
// the walk. The octree references a triangle from several cells, so a triangle already
// kept is not added twice.
struct AllQuery {
  static constexpr bool kOrdered = true;
  float ray_t_max;
  float t_max;
  HitRecord* hits;
  std::uint32_t capacity;
  std::uint32_t count = 0;

  TESSERA_KERNEL_INLINE bool leaf(const TriangleBlock4* blocks, std::uint32_t first,
                                  std::uint32_t n, const TriangleRay& r) {
    for (std::uint32_t b = first; b < first + n; ++b) {
      BlockHits found;
      std::uint32_t mask = intersect_block(blocks[b], r, t_max, found);
      while (mask != 0) {
        const auto lane = static_cast<std::uint32_t>(__builtin_ctz(mask));
        mask &= mask - 1;
        insert(HitRecord{lane_of(found.t, lane), lane_of(found.b1, lane), lane_of(found.b2, lane),
                         blocks[b].ids[lane]});
      }
    }
    return false;
  }

  void insert(const HitRecord& hit) {
    if (!(hit.t < t_max)) return;
    for (std::uint32_t i = 0; i < count; ++i)
      if (hits[i].primitive == hit.primitive) return;
    std::uint32_t at = count < capacity ? count++ : capacity - 1;
    while (at > 0 && hits[at - 1].t > hit.t) {
      hits[at] = hits[at - 1];
      --at;
    }
    hits[at] = hit;
    t_max = count == capacity ? hits[capacity - 1].t : ray_t_max;
  }
};

// ---- Walks -----------------------------------------------------------------------------

// Stack entries: the entry distance's bits above the child word (accel/wide_node_sse.hpp).
using wide_node_sse::key_distance;
using wide_node_sse::stack_key;
using wide_node_sse::StackKey;
inline void order(StackKey& a, StackKey& b) {  // a <= b afterwards
  const StackKey lo = a < b ? a : b, hi = a < b ? b : a;
  a = lo;
  b = hi;
}

// Requests the memory of every child the ray enters as soon as the node is tested: all
// four lines of an interior node, the first two triangle blocks of a leaf. The walk then
// waits for one miss where it waited for several in a row: the child word (the node's last
// line) is only read once the box test is done, siblings wait on the stack, and a leaf's
// blocks are read one pair after the other. Measured: +5% on diffuse rays (which miss the
// caches: the triangle blocks of a million triangles are several times the L3), no change
// on primary rays (bench/accel/README.md).
//
// Five lines from the child's start, unrolled: an interior node's four and the first line
// of its next sibling (siblings are allocated together), or a leaf's first two blocks (320
// bytes; the sixth line of a pair that starts mid-line is left to the walk). A loop over the exact
// byte count was 11% of all traversal instructions (bunny diffuse rays: 1,308 per ray with it,
// 1,164 without) and cost 2-4% of the speed of diffuse rays.
constexpr std::uint32_t kCacheLine = 64;
constexpr std::uint32_t kPrefetchedLines = 5;

TESSERA_KERNEL_INLINE void prefetch_children(const WideTriangleView& view, const WideBvhNode& node,
                                             std::uint32_t mask) {
  for (; mask != 0; mask &= mask - 1) {
    const std::uint32_t child = node.children[__builtin_ctz(mask)];
    const char* begin = wide_is_leaf(child)
                            ? reinterpret_cast<const char*>(view.blocks + wide_leaf_first(child))
                            : reinterpret_cast<const char*>(view.nodes + child);
    for (std::uint32_t line = 0; line < kPrefetchedLines; ++line)
      _mm_prefetch(begin + line * kCacheLine, _MM_HINT_T0);
  }
}

template <typename Query>
TESSERA_KERNEL_INLINE void traverse_wide(const WideTriangleView& view, const PreparedRay& ray,
                                         Query& query) {
  const BoxRay box_ray(ray);
  const TriangleRay triangle_ray(ray);
  StackKey stack[kWideStackSize];
  std::uint32_t size = 0;
  std::uint32_t child = 0;  // the root, always an interior node
  alignas(32) std::uint32_t entry[kWideBvhWidth];
  // The far planes' bound changes only when a leaf shortens t_max; formed at every node it
  // was a load, a multiply and a broadcast on each node test's path.
  float far_limit = query.t_max * kFarScale;
  // Read once: through `view`, whose address the walk keeps on the stack, the flag was two
  // loads per node.
  const bool prefetch = view.prefetch;
  for (;;) {
    while (!wide_is_leaf(child)) {
      const WideBvhNode& node = view.nodes[child];
      std::uint32_t mask = test_node(node, ray, box_ray, query.t_max, far_limit, entry);
      if (mask == 0) goto pop;
      if (prefetch) prefetch_children(view, node, mask);
      const auto first = static_cast<std::uint32_t>(__builtin_ctz(mask));
      mask &= mask - 1;
      if (mask == 0) {
        child = node.children[first];
        continue;
      }
      if constexpr (Query::kOrdered) {
        // Continue with the nearest child; the others wait on the stack, nearest on top.
        const auto second = static_cast<std::uint32_t>(__builtin_ctz(mask));
        mask &= mask - 1;
        StackKey k0 = stack_key(entry[first], node.children[first]);
        StackKey k1 = stack_key(entry[second], node.children[second]);
        order(k0, k1);
        if (mask == 0) {
          stack[size++] = k1;
          child = static_cast<std::uint32_t>(k0);
          continue;
        }
        const auto third = static_cast<std::uint32_t>(__builtin_ctz(mask));
        mask &= mask - 1;
        StackKey k2 = stack_key(entry[third], node.children[third]);
        if (mask == 0) {
          order(k1, k2);
          order(k0, k1);
          stack[size] = k2;
          stack[size + 1] = k1;
          size += 2;
          child = static_cast<std::uint32_t>(k0);
          continue;
        }
        const auto fourth = static_cast<std::uint32_t>(__builtin_ctz(mask));
        mask &= mask - 1;
        StackKey k3 = stack_key(entry[fourth], node.children[fourth]);
        if (mask == 0) {
          order(k2, k3);
          order(k0, k2);
          order(k1, k3);
          order(k1, k2);
          stack[size] = k3;
          stack[size + 1] = k2;
          stack[size + 2] = k1;
          size += 3;
          child = static_cast<std::uint32_t>(k0);
          continue;
        }
        // Five or more (rare): push all and insertion-sort them, farthest at the bottom.
        const std::uint32_t base = size;
        for (StackKey k : {k0, k1, k2, k3}) stack[size++] = k;
        do {
          const auto slot = static_cast<std::uint32_t>(__builtin_ctz(mask));
          mask &= mask - 1;
          stack[size++] = stack_key(entry[slot], node.children[slot]);
        } while (mask != 0);
        for (std::uint32_t i = base + 1; i < size; ++i) {
          const StackKey moving = stack[i];
          std::uint32_t j = i;
          for (; j > base && stack[j - 1] < moving; --j) stack[j] = stack[j - 1];
          stack[j] = moving;
        }
        child = static_cast<std::uint32_t>(stack[--size]);
      } else {
        do {
          const auto slot = static_cast<std::uint32_t>(__builtin_ctz(mask));
          mask &= mask - 1;
          stack[size++] = stack_key(entry[slot], node.children[slot]);
        } while (mask != 0);
        child = node.children[first];
      }
    }
    if (query.leaf(view.blocks, wide_leaf_first(child), wide_leaf_count(child), triangle_ray))
      return;
    far_limit = query.t_max * kFarScale;
  pop:
    StackKey popped;
    do {
      if (size == 0) return;
      popped = stack[--size];
    } while (key_distance(popped) > (query.t_max > 0.0f ? query.t_max : 0.0f));
    child = static_cast<std::uint32_t>(popped);
  }
}

template <typename Query>
TESSERA_KERNEL_INLINE void traverse_brute(const WideTriangleView& view, const PreparedRay& ray,
                                          Query& query) {
  const TriangleRay triangle_ray(ray);
  for (std::uint32_t b = 0; b < view.block_count; ++b)
    if (query.leaf(view.blocks, b, 1, triangle_ray)) return;
}

template <bool kBrute, typename Query>
TESSERA_KERNEL_INLINE void walk(const WideTriangleView& view, const PreparedRay& ray,
                                Query& query) {
  if constexpr (kBrute) {
    traverse_brute(view, ray, query);
  } else {
    if (view.nodes != nullptr) traverse_wide(view, ray, query);
  }
}

// prepare for the structure's walk: the wide walks test the root's box first; an empty
// structure (no root) traces nothing.
template <bool kBrute>
TESSERA_KERNEL_INLINE bool prepare_for(const WideTriangleView& view, const Ray& ray,
                                       PreparedRay& r) {
  if constexpr (kBrute) {
    return prepare<false>(ray, nullptr, r);
  } else {
    return view.root_box != nullptr && prepare<true>(ray, view.root_box, r);
  }
}

template <bool kBrute>
bool closest(const WideTriangleView& view, const Ray& ray, HitRecord& hit) {
  PreparedRay prepared;
  if (!prepare_for<kBrute>(view, ray, prepared)) return false;
  ClosestQuery query{ray.t_max};
  walk<kBrute>(view, prepared, query);
  if (query.found) hit = query.best;
  return query.found;
}

template <bool kBrute>
bool occluded(const WideTriangleView& view, const Ray& ray) {
  PreparedRay prepared;
  if (!prepare_for<kBrute>(view, ray, prepared)) return false;
  AnyQuery query{ray.t_max};
  walk<kBrute>(view, prepared, query);
  return query.found;
}

template <bool kBrute>
std::uint32_t all_hits(const WideTriangleView& view, const Ray& ray, HitRecord* hits,
                       std::uint32_t capacity) {
  PreparedRay prepared;
  if (capacity == 0 || !prepare_for<kBrute>(view, ray, prepared)) return 0;
  AllQuery query{ray.t_max, ray.t_max, hits, capacity};
  walk<kBrute>(view, prepared, query);
  return query.count;
}

template <bool kBrute>
void closest_batch(const WideTriangleView& view, const Ray* rays, HitRecord* hits,
                   std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    hits[i] = HitRecord{};
    closest<kBrute>(view, rays[i], hits[i]);
  }
}

template <bool kBrute>
void occluded_batch(const WideTriangleView& view, const Ray* rays, std::uint8_t* result,
                    std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) result[i] = occluded<kBrute>(view, rays[i]) ? 1 : 0;
}

template <bool kBrute>
constexpr TriangleKernels make_kernels(std::string_view isa) {
  return TriangleKernels{isa,
                         &closest<kBrute>,
                         &occluded<kBrute>,
                         &all_hits<kBrute>,
                         &closest_batch<kBrute>,
                         &occluded_batch<kBrute>};
}

}  // namespace

const TriangleKernels& wide_kernels() {
  static constexpr TriangleKernels kernels = make_kernels<false>(TESSERA_KERNEL_ISA_NAME);
  return kernels;
}

const TriangleKernels& brute_kernels() {
  static constexpr TriangleKernels kernels = make_kernels<true>(TESSERA_KERNEL_ISA_NAME);
  return kernels;
}

}  // namespace tessera::accel_detail::TESSERA_KERNEL_NS
