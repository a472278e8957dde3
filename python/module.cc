// The Python module tissuebench (docs/python.md): the registry, scenario and
// experiment files, and one case stepped from Python, over the same C++ the
// tissuebench program runs. Every error the C++ raises (a bad file, an unknown
// model, a diverged case) reaches Python as tissuebench.Error carrying the one line
// the program prints after "tissuebench: ".
#include <pybind11/pybind11.h>

#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "blas_kernels.h"
#include "elastic_body.h"
#include "python_bindings.h"

namespace tb::python {

py::object to_python(const nlohmann::json& value) { return py::module_::import("json").attr("loads")(value.dump()); }

nlohmann::json from_python(const py::handle& value, const std::string& what) {
  std::string text;
  try {
    text = py::module_::import("json").attr("dumps")(value).cast<std::string>();
  } catch (const py::error_already_set& e) {
    throw std::invalid_argument(what + ": not representable as JSON (" + std::string(e.what()) + ")");
  }
  return nlohmann::json::parse(text);
}

}  // namespace tb::python

PYBIND11_MODULE(_tissuebench, m) {
  namespace py = pybind11;
  m.doc() =
      "tissuebench's C++ core: the model registry, scenario and experiment files, and one case stepped from "
      "Python (docs/python.md). Import the package `tissuebench`, not this module.";
  // Every reported time single-threaded, as the tissuebench program runs (elastic_body.h).
  tb::use_one_thread();

  // Never destroyed: the module's exception type outlives the interpreter's finalisation.
  static auto* const error = new py::exception<std::exception>(m, "Error");
  error->doc() =
      "An error of tissuebench's C++ core: one line naming the file and the problem, the line the tissuebench "
      "program prints after 'tissuebench: '.";
  // Errors of pybind11's own (wrong argument types, a Python exception raised inside a
  // call) and running out of memory keep their Python types; every other C++ error
  // becomes tissuebench.Error.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const py::builtin_exception&) {
      throw;
    } catch (const py::error_already_set&) {
      throw;
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      (*error)(e.what());
    }
  });

  m.def("blas_core", &tb::blas_core_name,
        "The OpenBLAS kernels in use (e.g. 'Haswell'): the tissuebench program pins kPinnedBlasCore "
        "(experiments/blas_kernels.h) and so does `import tissuebench`, when it loads OpenBLAS first.");
  m.attr("pinned_blas_core") = tb::kPinnedBlasCore;

  tb::python::bind_registry(m);
  tb::python::bind_scenarios(m);
  tb::python::bind_run(m);
}
