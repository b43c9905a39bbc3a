// What the binding sources of the `pfx` Python module share: the world as Python holds it,
// shapes that keep their meshes alive, errors, and conversions between numpy and pfx's
// math types. The module adds no physics: every call goes to the public C++ API.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "pfx/pfx.h"

namespace pfx::python {

namespace py = pybind11;

// A world and what its bodies point into (meshes, the models that own them). The
// resources are declared first so that they outlive the world.
class PyWorld {
 public:
  std::vector<std::shared_ptr<const void>> resources;
  PfxWorld world;
  // Zero-copy state arrays handed out and still alive: while there are any, nothing may
  // move or drop the world's state buffer.
  int liveStateViews = 0;
  // Counts initialize, load and truncate: models loaded before a change of generation name
  // bodies that may be gone.
  PfxUInt64 generation = 0;
  // The character controllers of this generation: their characters' bodies are theirs to
  // remove (remove_body refuses them), as the controller would go on driving a gone body.
  std::vector<const PfxCharacterController*> characterControllers;

  // Raises pfx.Error when a state view is alive, as `what` would leave it dangling.
  void requireNoStateViews(const char* what) const;
  // Raises pfx.Error when `body` is a character's of one of characterControllers.
  void requireNotCharacterBody(PfxUInt32 body) const;
  // Marks bodies gone: every earlier model goes stale, and the resources they used go too
  // when `dropResources` (the world was emptied).
  void startGeneration(bool dropResources);
};

// One shape and the mesh it points to, if any: the shape is copied into bodies, the mesh
// must live as long as they do.
struct PyShape {
  PfxShape shape;
  std::shared_ptr<const void> mesh;
};

// A model loaded into a world (URDF, scene file, OctoMap) and the world it belongs to, which
// the Python object keeps alive.
template <typename Model>
struct PyLoaded {
  std::shared_ptr<Model> model;
  PyWorld* owner;
  PfxUInt64 generation;

  // The model, or pfx.Error when the world was re-initialized, loaded or truncated since.
  const Model& current() const;
};

// A read-only (rows, columns) array of PfxFloat over the world's own memory (rows
// rowBytes apart), without a copy: it keeps the world alive and counts as a live state
// view, so that calls that would move or free that memory raise while it lives.
py::array worldMemoryView(const py::object& worldObject, const void* data, py::ssize_t rows,
                          py::ssize_t columns, std::size_t rowBytes);

// Raises pfx.Error (pfx.InvalidValueError for bad values) for an error code, with
// pfxErrorString and the caller's message. PFX_OK returns.
void raiseIfError(PfxInt32 code, const std::string& message = std::string());
// As raiseIfError, adding pfxGetLastErrorDetail() when the failed call wrote a new one.
class ErrorDetailWatch {
 public:
  ErrorDetailWatch();
  void raiseIfError(PfxInt32 code) const;

 private:
  std::string m_before;
};

// Refuses a negative count, then runs stepping(count) with the GIL released, so that other
// Python threads run while worlds and batches step alike; returns its error code.
template <typename Stepping>
PfxInt32 stepWithoutGil(long count, const Stepping& stepping) {
  if (count < 0) raiseIfError(PFX_ERR_INVALID_VALUE, "step count is negative");
  py::gil_scoped_release release;
  return stepping(count);
}

// numpy and sequences to pfx's types: a vector is 3 numbers, a quaternion 4 as (x, y, z, w).
PfxVector3 toVector3(py::handle value, const char* name);
PfxQuat toQuat(py::handle value, const char* name);
py::array_t<PfxFloat> fromVector3(const PfxVector3& v);
// A new (rows, columns) array.
template <typename T>
py::array_t<T> newArray(py::ssize_t rows, py::ssize_t columns) {
  return py::array_t<T>(std::vector<py::ssize_t>{rows, columns});
}
py::array_t<PfxFloat> fromQuat(const PfxQuat& q);
// An (n, columns) array of PfxFloat, C-contiguous, converted if needed.
py::array_t<PfxFloat, py::array::c_style | py::array::forcecast> toRows(py::handle value,
                                                                          py::ssize_t columns,
                                                                          const char* name);

// Properties of plain structs (the member may belong to a base): vectors and quaternions read as numpy arrays and set from any
// sequence.
template <typename T, typename Owner>
void defVector3(py::class_<T>& cls, const char* name, PfxVector3 Owner::*member, const char* doc) {
  cls.def_property(
      name, [member](const T& t) { return fromVector3(t.*member); },
      [member, name](T& t, py::handle v) { t.*member = toVector3(v, name); }, doc);
}
template <typename T, typename Owner>
void defQuat(py::class_<T>& cls, const char* name, PfxQuat Owner::*member, const char* doc) {
  cls.def_property(
      name, [member](const T& t) { return fromQuat(t.*member); },
      [member, name](T& t, py::handle v) { t.*member = toQuat(v, name); }, doc);
}

// A constructor taking any of the struct's properties as keywords, the rest at their C++
// defaults: pfx.WorldParam(time_step=1/240, enable_sleep=False).
template <typename T>
void defKeywordInit(py::class_<T>& cls, const char* doc) {
  cls.def(py::init([](const py::kwargs& keywords) {
            py::object object = py::cast(T());
            const py::object type = py::type::of(object);
            for (const auto& item : keywords) {
              if (!py::hasattr(type, item.first)) {
                throw py::type_error(py::str("{}() has no field '{}'")
                                         .format(type.attr("__name__"), item.first));
              }
              py::setattr(object, item.first, item.second);
            }
            return object.cast<T>();
          }),
          doc);
}

// One per area, called by the module's init in this order (later ones use earlier types).
void bindErrors(py::module_& m);
void bindShapes(py::module_& m);
void bindWorld(py::module_& m);
void bindBodies(py::module_& m);
void bindJoints(py::module_& m);
void bindQueries(py::module_& m);
void bindSerialization(py::module_& m);
void bindBatch(py::module_& m);
void bindParticles(py::module_& m);
void bindCharacters(py::module_& m);
#ifdef PFX_PYTHON_HAVE_LOADERS
void bindLoaders(py::module_& m);
#endif
#ifdef PFX_PYTHON_HAVE_PICTURE
void bindRender(py::module_& m);
#endif

template <typename Model>
const Model& PyLoaded<Model>::current() const {
  if (generation != owner->generation) {
    raiseIfError(PFX_ERR_OUT_OF_RANGE,
                 "the world was initialized, loaded or truncated after this model was loaded; "
                 "its bodies are gone");
  }
  return *model;
}

}  // namespace pfx::python
