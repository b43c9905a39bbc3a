// Saving a world to a file and loading it back (pfx_serialize.h): the loaded world steps
// exactly as the saved one would have.
#include "pfx_python.h"

namespace pfx::python {

namespace {

// The file, then what the serializer said about it, if anything.
std::string aboutFile(const std::string& path, const std::string& message) {
  return message.empty() ? path : path + ": " + message;
}

}  // namespace

void bindSerialization(py::module_& m) {
  py::class_<PyWorld>(m.attr("World"))
      .def(
          "save",
          [](const PyWorld& w, const std::string& path) {
            std::string message;
            raiseIfError(pfxSaveWorld(w.world, path.c_str(), &message), aboutFile(path, message));
          },
          py::arg("path"),
          "Writes the whole world (bodies, joints, contacts with their impulses, sleep) to path.")
      .def(
          "load",
          [](PyWorld& w, const std::string& path, py::object numThreads) {
            w.requireNoStateViews("load");
            PfxLoadWorldOptions options;
            if (!numThreads.is_none()) {
              options.keepSavedNumThreads = false;
              options.numThreads = numThreads.cast<PfxUInt32>();
            }
            auto meshes = std::make_shared<PfxSerializedMeshes>();
            std::string message;
            raiseIfError(pfxLoadWorld(w.world, path.c_str(), *meshes, &message, options),
                         aboutFile(path, message));
            w.startGeneration(true);
            w.resources.push_back(std::move(meshes));
          },
          py::arg("path"), py::arg("num_threads") = py::none(),
          "Replaces everything with a world saved by save() (its parameters too; num_threads,\n"
          "when given, replaces the saved thread count). On error the world is unchanged.");
}

}  // namespace pfx::python
