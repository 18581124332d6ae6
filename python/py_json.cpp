#include "py_json.h"

#include <cmath>

#include "drape/error.h"

namespace drape::python {

namespace py = pybind11;
using nlohmann::json;

namespace {

std::string type_name(const py::handle& value) {
  return py::str(py::type::handle_of(value).attr("__qualname__"));
}

std::string item_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

}  // namespace

json to_json(const py::handle& value, const std::string& path) {
  const std::string where = path.empty() ? "(top level)" : path;
  if (value.is_none()) return nullptr;
  // bool before int: Python's bool is an int.
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::int_>(value)) {
    try {
      return value.cast<int64_t>();
    } catch (const py::cast_error&) {
      return py::cast<double>(py::float_(py::reinterpret_borrow<py::object>(value)));
    }
  }
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::dict>(value)) {
    json object = json::object();
    for (const auto& [key, item] : py::reinterpret_borrow<py::dict>(value)) {
      if (!py::isinstance<py::str>(key))
        throw InputError(where, "keys must be strings, got " + type_name(key) + " " +
                                    std::string(py::repr(key)));
      const std::string name = key.cast<std::string>();
      object[name] = to_json(item, item_path(path, name));
    }
    return object;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    json array = json::array();
    size_t k = 0;
    for (const py::handle item : value)
      array.push_back(to_json(item, path + "[" + std::to_string(k++) + "]"));
    return array;
  }
  // NumPy: arrays as their lists, scalars (numpy.float64, numpy.int32, numpy.bool_) as the
  // Python values they stand for.
  const py::module_ numpy = py::module_::import("numpy");
  if (py::isinstance(value, numpy.attr("ndarray")) || py::isinstance(value, numpy.attr("generic")))
    return to_json(value.attr("tolist")(), path);
  throw InputError(where,
                   "expected a dict, list, str, number, bool or None, got " + type_name(value));
}

py::object to_python(const json& value) {
  switch (value.type()) {
    case json::value_t::null:
      return py::none();
    case json::value_t::boolean:
      return py::bool_(value.get<bool>());
    case json::value_t::number_integer:
      return py::int_(value.get<int64_t>());
    case json::value_t::number_unsigned:
      return py::int_(value.get<uint64_t>());
    case json::value_t::number_float:
      return py::float_(value.get<double>());
    case json::value_t::string:
      return py::str(value.get<std::string>());
    case json::value_t::array: {
      py::list list;
      for (const json& item : value) list.append(to_python(item));
      return list;
    }
    case json::value_t::object: {
      py::dict dict;
      for (auto it = value.begin(); it != value.end(); ++it)
        dict[py::str(it.key())] = to_python(it.value());
      return dict;
    }
    default:
      return py::none();  // binary and discarded values never come from drape
  }
}

}  // namespace drape::python
