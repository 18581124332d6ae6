// The one exception type of the library: bad input, rejected at the boundary.
#pragma once

#include <stdexcept>
#include <string>

namespace drape {

/// Bad input. `path` names the field as a JSON-style path ("cloth.springs.shear.stiffness",
/// "colliders[1].radius"); empty when the problem is not one field's.
class InputError : public std::runtime_error {
 public:
  InputError(std::string path, const std::string& problem)
      : std::runtime_error(path.empty() ? problem : path + ": " + problem),
        path_(std::move(path)),
        problem_(problem) {}
  const std::string& path() const { return path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string path_;
  std::string problem_;
};

}  // namespace drape
