#pragma once
// Metadata values between Python and the library's Attribute (io.hpp), one way for every source:
// the user's write(metadata=...) and the openimageio package's attributes.
#include <pybind11/pybind11.h>

#include <optional>

#include "panoproj/io.hpp"

namespace panoproj {

// int/bool -> integer, float, str, bytes or a uint8 numpy array -> bytes, any other numpy array or
// a sequence of numbers -> floats; anything else: none.
std::optional<Attribute::Value> attribute_value(const pybind11::handle& v);
// The value as Python has it: int, float, str, bytes, a tuple of floats.
pybind11::object python_value(const Attribute& a);

}  // namespace panoproj
