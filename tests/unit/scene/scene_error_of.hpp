#pragma once
// What the loader tests share: the SceneError a load raises, or a test failure when it
// raises none.
#include <gtest/gtest.h>

#include "tessera/scene/scene_error.hpp"

namespace tessera::test {

template <typename Load>
SceneIssue scene_error_of(Load&& load, const std::string& what) {
  try {
    load();
  } catch (const SceneError& e) {
    return e.issue();
  }
  ADD_FAILURE() << "expected a SceneError for:\n" << what;
  return {};
}

}  // namespace tessera::test
