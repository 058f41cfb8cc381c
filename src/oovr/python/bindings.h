// The native part of the oovr Python module (_oovr), shared between its
// two files: module.cpp (scenes, configurations, rendering, simulation,
// sweeps) and schemes.cpp (schemes written in Python). Python code never
// sees this header; oovr/__init__.py is the module users import.
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "oovr/schemes/i_scheme.h"

namespace oovr::python {

namespace py = pybind11;

// A JSON value as the Python value json.loads would give.
py::object to_python(const nlohmann::ordered_json& j);

// The name of `v`'s type, for messages ("NoneType", "str").
std::string type_name(const py::handle& v);

// `v` as a Python int when it is a whole number: an int, or what has
// __index__ (numpy's integers); not a bool. A null object otherwise.
py::object as_int(const py::handle& v);

// `v` as a whole number (as_int): TypeError naming `what` for anything
// else, an Error (ValueError) when it does not fit 64 bits. The caller
// checks the range.
int64_t whole(const py::handle& v, const std::string& what);

// The scheme `s` names: a registered scheme's name (str), or a Python
// object with a run(input) method (docs/python.md, "Schemes in Python").
// Throws Error for an unknown name, TypeError for anything else.
SchemeRef scheme_of(const py::handle& s);

// Adds the classes and functions for schemes written in Python.
void bind_schemes(py::module_& m);

}  // namespace oovr::python
