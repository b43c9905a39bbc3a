// pfx's error codes as Python exceptions, the conversions every binding uses, and the
// world's guard of its zero-copy state arrays.
#include <algorithm>

#include "pfx/low_level/pfx_error_detail.h"
#include "pfx_python.h"

namespace pfx::python {

namespace {

// Created once by bindErrors; the module holds them for the life of the interpreter.
PyObject* g_error = nullptr;
PyObject* g_invalidValueError = nullptr;

// Codes that say a value the caller gave was wrong, rather than that pfx ran out of room.
bool isBadValue(PfxInt32 code) {
  return code == PFX_ERR_INVALID_VALUE || code == PFX_ERR_INVALID_FLAG ||
         code == PFX_ERR_OUT_OF_RANGE || code == PFX_ERR_DEGENERATE || code == PFX_ERR_NOT_CONVEX;
}

}  // namespace

void raiseIfError(PfxInt32 code, const std::string& message) {
  if (code == PFX_OK) return;
  std::string text = pfxErrorString(code);
  if (!message.empty()) text += ": " + message;
  const py::handle type = isBadValue(code) ? g_invalidValueError : g_error;
  py::object exception = py::reinterpret_borrow<py::object>(type)(text);
  exception.attr("code") = code;
  PyErr_SetObject(type.ptr(), exception.ptr());
  throw py::error_already_set();
}

ErrorDetailWatch::ErrorDetailWatch() : m_before(pfxGetLastErrorDetail()) {}

void ErrorDetailWatch::raiseIfError(PfxInt32 code) const {
  if (code == PFX_OK) return;
  const std::string detail = pfxGetLastErrorDetail();
  python::raiseIfError(code, detail != m_before ? detail : std::string());
}

void PyWorld::requireNoStateViews(const char* what) const {
  if (liveStateViews == 0) return;
  raiseIfError(PFX_ERR_INVALID_VALUE,
               std::string(what) + " would move or drop the state buffer that " +
                   std::to_string(liveStateViews) +
                   " live zero-copy state array(s) read; copy them (.copy()) or delete them first");
}

void PyWorld::startGeneration(bool dropResources) {
  ++generation;
  characterControllers.clear();
  if (dropResources) resources.clear();
}

PfxVector3 toVector3(py::handle value, const char* name) {
  const auto array = py::array_t<double, py::array::forcecast>::ensure(value);
  if (!array || array.ndim() != 1 || array.shape(0) != 3) {
    throw py::value_error(std::string(name) + " must be 3 numbers");
  }
  return PfxVector3(PfxFloat(array.at(0)), PfxFloat(array.at(1)), PfxFloat(array.at(2)));
}

PfxQuat toQuat(py::handle value, const char* name) {
  const auto array = py::array_t<double, py::array::forcecast>::ensure(value);
  if (!array || array.ndim() != 1 || array.shape(0) != 4) {
    throw py::value_error(std::string(name) + " must be 4 numbers (x, y, z, w)");
  }
  return PfxQuat(PfxFloat(array.at(3)), PfxFloat(array.at(0)), PfxFloat(array.at(1)),
                 PfxFloat(array.at(2)));
}

py::array_t<PfxFloat> fromVector3(const PfxVector3& v) {
  py::array_t<PfxFloat> array(3);
  std::copy(v.data(), v.data() + 3, array.mutable_data());
  return array;
}

py::array_t<PfxFloat> fromQuat(const PfxQuat& q) {
  py::array_t<PfxFloat> array(4);
  std::copy(q.coeffs().data(), q.coeffs().data() + 4, array.mutable_data());
  return array;
}

py::array_t<PfxFloat, py::array::c_style | py::array::forcecast> toRows(py::handle value,
                                                                          py::ssize_t columns,
                                                                          const char* name) {
  auto array = py::array_t<PfxFloat, py::array::c_style | py::array::forcecast>::ensure(value);
  if (array && array.ndim() == 1 && array.shape(0) == columns) {
    array = array.reshape(std::vector<py::ssize_t>{1, columns});
  }
  if (!array || array.ndim() != 2 || array.shape(1) != columns) {
    throw py::value_error(std::string(name) + " must be an array of shape (n, " +
                          std::to_string(columns) + ")");
  }
  return array;
}

void bindErrors(py::module_& m) {
  g_error = PyErr_NewExceptionWithDoc(
      "pfx.Error",
      "A call pfx rejected. str() is pfxErrorString of the code, then what pfx said about it\n"
      "(the file, element and reason for loaders); .code is the PFX_ERR_* value. The call\n"
      "changed nothing.",
      PyExc_RuntimeError, nullptr);
  const py::tuple bases = py::make_tuple(py::handle(g_error), py::handle(PyExc_ValueError));
  g_invalidValueError = PyErr_NewExceptionWithDoc(
      "pfx.InvalidValueError",
      "A pfx.Error for a value pfx rejected (NaN, negative mass, index out of range, a\n"
      "degenerate or non-convex mesh, a malformed file); also a ValueError.",
      bases.ptr(), nullptr);
  m.attr("Error") = py::handle(g_error);
  m.attr("InvalidValueError") = py::handle(g_invalidValueError);
  m.attr("OK") = int(PFX_OK);
  m.attr("ERR_INVALID_VALUE") = int(PFX_ERR_INVALID_VALUE);
  m.attr("ERR_INVALID_ALIGNMENT") = int(PFX_ERR_INVALID_ALIGNMENT);
  m.attr("ERR_OUT_OF_BUFFER") = int(PFX_ERR_OUT_OF_BUFFER);
  m.attr("ERR_OUT_OF_WORLD") = int(PFX_ERR_OUT_OF_WORLD);
  m.attr("ERR_OUT_OF_MAX_PAIRS") = int(PFX_ERR_OUT_OF_MAX_PAIRS);
  m.attr("ERR_INVALID_FLAG") = int(PFX_ERR_INVALID_FLAG);
  m.attr("ERR_NOT_CONVEX") = int(PFX_ERR_NOT_CONVEX);
  m.attr("ERR_OUT_OF_RANGE") = int(PFX_ERR_OUT_OF_RANGE);
  m.attr("ERR_DEGENERATE") = int(PFX_ERR_DEGENERATE);
  m.attr("ERR_NULL_POINTER") = int(PFX_ERR_NULL_POINTER);
  m.def("error_string", &pfxErrorString, py::arg("code"), "pfxErrorString: an error code in words.");
}

}  // namespace pfx::python
