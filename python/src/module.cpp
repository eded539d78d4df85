// The extension module ldoem._ldoem; the package ldoem (python/ldoem/__init__.py) re-exports it.
#include <pybind11/pybind11.h>

#include "convert.hpp"
#include "scanner_binding.hpp"

PYBIND11_MODULE(_ldoem, m) {
  m.doc() = "libldoem for Python: ldoem.Scanner, ldoem.scan (docs/python.md)";
  m.attr("__version__") = LDOEM_PYTHON_VERSION;
  ldoem::python::register_profile_dtype(m);
  ldoem::python::bind_scanner(m);
  ldoem::python::bind_scan(m);
}
