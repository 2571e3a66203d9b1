#include "attribute_values.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <type_traits>
#include <variant>

namespace py = pybind11;

namespace panoproj {

std::optional<Attribute::Value> attribute_value(const py::handle& v) {
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::bool_>(v) || py::isinstance<py::int_>(v)) return v.cast<int64_t>();
  if (py::isinstance<py::float_>(v)) return v.cast<double>();
  if (py::isinstance<py::bytes>(v)) {
    const std::string b = v.cast<std::string>();
    return std::vector<uint8_t>(b.begin(), b.end());
  }
  if (py::isinstance<py::array>(v)) {
    const auto a = py::array::ensure(v);
    if (a.dtype().kind() == 'u' && a.itemsize() == 1) {
      const auto u8 = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(v);
      return std::vector<uint8_t>(u8.data(), u8.data() + u8.size());
    }
    if (a.dtype().kind() != 'u' && a.dtype().kind() != 'i' && a.dtype().kind() != 'f') return std::nullopt;
    const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(v);
    return std::vector<double>(d.data(), d.data() + d.size());
  }
  if (py::isinstance<py::sequence>(v)) {
    std::vector<double> out;
    for (const auto& x : v.cast<py::sequence>()) {
      if (!py::isinstance<py::int_>(x) && !py::isinstance<py::float_>(x)) return std::nullopt;
      out.push_back(x.cast<double>());
    }
    return out;
  }
  return std::nullopt;
}

py::object python_value(const Attribute& a) {
  return std::visit(
      [](const auto& v) -> py::object {
        using V = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<V, std::vector<uint8_t>>) {
          return py::bytes(reinterpret_cast<const char*>(v.data()), v.size());
        } else if constexpr (std::is_same_v<V, std::vector<double>>) {
          return py::tuple(py::cast(v));
        } else {
          return py::cast(v);
        }
      },
      a.value);
}

}  // namespace panoproj
