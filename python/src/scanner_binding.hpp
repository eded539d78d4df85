// ldoem.Scanner: libldoem's Scanner over any endpoint the C++ tools accept, plus the tilt
// stepper on an LPT endpoint. Not thread-safe (one thread per Scanner, as in C++).
#pragma once

#include <pybind11/pybind11.h>

namespace ldoem::python {

void bind_scanner(pybind11::module_& module);
void bind_scan(pybind11::module_& module);

}  // namespace ldoem::python
