#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera {

// A problem with a scene, located by field path (`geometry[3].radius`) and, when the scene
// came from a file, by file and line. Errors are values: loaders collect them and callers
// decide whether to throw, print or map them to a gRPC status.
struct SceneIssue {
  std::string file;   // empty when the scene did not come from a file
  int line = 0;       // 1-based; 0 when unknown
  std::string field;  // path such as `materials[2].roughness`; empty for whole-file problems
  std::string message;

  // `scene.yaml:12: geometry[3].radius: must be > 0, got -1`
  std::string to_string() const;
};

class SceneError : public std::runtime_error {
 public:
  explicit SceneError(SceneIssue issue)
      : std::runtime_error(issue.to_string()), issue_(std::move(issue)) {}
  const SceneIssue& issue() const { return issue_; }

 private:
  SceneIssue issue_;
};

}  // namespace tessera
