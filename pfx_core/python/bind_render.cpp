// A picture of the world as PNG, drawn by the debug render's shapes (PfxScenePicture).
#include "pfx_python.h"
#include "pfx_scene_picture.h"

namespace pfx::python {

void bindRender(py::module_& m) {
  py::class_<PyWorld>(m.attr("World"))
      .def(
          "render_png",
          [](const PyWorld& w, const std::string& path, PfxUInt32 width, PfxUInt32 height,
             py::handle eye, py::handle target, py::handle up, PfxFloat fieldOfView,
             bool drawContacts) {
            PfxScenePicture picture(width, height);
            picture.setDrawContacts(drawContacts);
            if (!eye.is_none() || !target.is_none()) {
              PfxSceneCamera camera = PfxScenePicture::frameScene(
                  w.world, up.is_none() ? PfxVector3(-w.world.getParam().gravity.normalized())
                                        : toVector3(up, "up"),
                  fieldOfView);
              if (!eye.is_none()) camera.position = toVector3(eye, "eye");
              if (!target.is_none()) camera.target = toVector3(target, "target");
              raiseIfError(picture.setCamera(camera), "camera");
            }
            std::string message;
            raiseIfError(picture.draw(w.world, path, &message), message);
            return picture.getNumDrawnTriangles();
          },
          py::arg("path"), py::arg("width") = 1280, py::arg("height") = 960,
          py::arg("eye") = py::none(), py::arg("target") = py::none(), py::arg("up") = py::none(),
          py::arg("field_of_view") = 40, py::arg("draw_contacts") = true,
          "Draws the world (shapes flat-shaded, a ground grid, contact points) to a PNG file.\n"
          "Without eye and target the camera frames every moving body, up against gravity.\n"
          "Returns the number of triangles drawn.");
}

}  // namespace pfx::python
