// The Python face of the engine: a thin layer over the C++ core. Heavy calls release the GIL.
#include <pybind11/pybind11.h>

namespace py = pybind11;

#ifdef _WIN32
// A Windows CPython's pyconfig.h takes pointers to be 4 bytes unless MS_WIN64 is defined, which
// it does only for MSVC: a module built otherwise would misread every object.
static_assert(SIZEOF_VOID_P == 8 && sizeof(void*) == 8, "build the Windows module with -DMS_WIN64");
#endif

namespace mwb::python {
void bind_scene(py::module_& m);
void bind_sampler(py::module_& m);
void bind_library(py::module_& m);
void bind_query(py::module_& m);
void bind_run(py::module_& m);
}  // namespace mwb::python

PYBIND11_MODULE(_native, m) {
    m.doc() = "Many-Worlds Browser native engine: scenes, plausible-world sampling, recorded motion.";
    mwb::python::bind_scene(m);
    mwb::python::bind_sampler(m);
    mwb::python::bind_library(m);
    mwb::python::bind_query(m);
    mwb::python::bind_run(m);
}
