#pragma once
#include <cstddef>
#include <tuple>
#include <type_traits>
#include <vector>

#include "tessera/render/scene_data.hpp"

namespace tessera {

namespace scene_detail {

// The shape type a listed primitive's SceneShapes array points to.
template <typename Primitive>
using StoredShape = std::remove_cv_t<std::remove_pointer_t<
    std::remove_cvref_t<decltype(std::declval<SceneShapes&>().*Primitive::array)>>>;

template <typename List>
struct HostArraysOf;
template <typename... P>
struct HostArraysOf<PrimitiveList<P...>> {
  using type = std::tuple<std::vector<StoredShape<P>>...>;
};

}  // namespace scene_detail

// The host storage of a render scene: one flat array per stored primitive type, made from
// the same list the renderer dispatches over (scene_detail::StoredPrimitives), so a new
// primitive type needs no new member here or in PreparedScene::view().
class PrimitiveArrays {
 public:
  template <PrimitiveType kType>
  auto& of() {
    return std::get<static_cast<std::size_t>(kType)>(arrays_);
  }
  template <PrimitiveType kType>
  const auto& of() const {
    return std::get<static_cast<std::size_t>(kType)>(arrays_);
  }

  // Points every array of `shapes` at this storage, and sets the plane count.
  void bind(SceneShapes& shapes) const { bind_listed(scene_detail::StoredPrimitives{}, shapes); }

 private:
  template <typename... P>
  void bind_listed(scene_detail::PrimitiveList<P...>, SceneShapes& shapes) const {
    ((shapes.*P::array = of<P::tag>().data()), ...);
    shapes.plane_count = static_cast<std::uint32_t>(of<PrimitiveType::kPlane>().size());
  }

  // Indexed by PrimitiveType: StoredPrimitives lists the types in tag order (static_assert).
  typename scene_detail::HostArraysOf<scene_detail::StoredPrimitives>::type arrays_;
};

}  // namespace tessera
