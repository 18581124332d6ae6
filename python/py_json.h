// Python values to JSON and back, so that a scene given as a dict goes through the same parser,
// checks and messages as a scene file, and stats come back as a dict.
#pragma once

#include <string>

#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

namespace drape::python {

/// dict, list, tuple, str, int, float, bool and None, and NumPy's scalars and arrays (as their
/// lists). Throws drape::InputError naming `path` (a JSON-style path) for anything else, or for
/// a dict key that is not a string.
nlohmann::json to_json(const pybind11::handle& value, const std::string& path);

/// JSON to dict, list, str, int, float, bool and None.
pybind11::object to_python(const nlohmann::json& value);

}  // namespace drape::python
