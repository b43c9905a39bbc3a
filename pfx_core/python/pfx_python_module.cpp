// The extension `pfx._core`, which the package `pfx` re-exports: pfx's public C++ API for
// scripts, states and query results as numpy arrays. See the README's "Python" section.
#include "pfx_python.h"

PYBIND11_MODULE(_core, m) {
  using namespace pfx::python;
  m.doc() =
      "pfx: real-time rigid-body physics (after Sony's Physics Effects).\n\n"
      "Build a World, add bodies (add_body, load_urdf, load_scene, load_octomap), step it and\n"
      "read its states as numpy arrays. Vectors are 3 numbers, quaternions 4 as (x, y, z, w).\n"
      "A call that pfx rejects raises pfx.Error with pfx's message and changes nothing.";
  m.attr("FLOAT_DTYPE") = py::dtype::of<pfx::PfxFloat>();
  bindErrors(m);
  bindShapes(m);
  bindWorld(m);
  bindBodies(m);
  bindJoints(m);
  bindQueries(m);
  bindSerialization(m);
  bindBatch(m);
  bindParticles(m);
  bindCharacters(m);
#ifdef PFX_PYTHON_HAVE_LOADERS
  bindLoaders(m);
#endif
#ifdef PFX_PYTHON_HAVE_PICTURE
  bindRender(m);
#endif
}
