// Adding bodies: PfxBodyInit and pfxAddBody, one shape or a compound of up to 64.
#include <pybind11/stl.h>

#include "pfx_python.h"

namespace pfx::python {

void bindBodies(py::module_& m) {
  py::enum_<PfxMotionType>(m, "MotionType", "The five motion types of seed chapter 2.")
      .value("FIXED", kPfxMotionTypeFixed, "Never moves.")
      .value("ACTIVE", kPfxMotionTypeActive, "Moved by forces and contacts.")
      .value("KEYFRAME", kPfxMotionTypeKeyframe, "Moved by the application (set_keyframe_target).")
      .value("ONE_WAY", kPfxMotionTypeOneWay, "Pushed by others, pushes none.")
      .value("TRIGGER", kPfxMotionTypeTrigger, "Reports contacts, no response.");

  py::class_<PfxBodyInit> bodyInit(m, "BodyInit",
                               "PfxBodyInit: pose, velocities, mass (0: fixed), friction,\n"
                               "restitution and motion type of a body to add.");
  defKeywordInit(bodyInit, "Any field as a keyword; the rest keep pfx's defaults.");
  defVector3(bodyInit, "position", &PfxBodyInit::position, "m.");
  defQuat(bodyInit, "orientation", &PfxBodyInit::orientation, "(x, y, z, w).");
  defVector3(bodyInit, "linear_velocity", &PfxBodyInit::linearVelocity, "m/s.");
  defVector3(bodyInit, "angular_velocity", &PfxBodyInit::angularVelocity, "rad/s.");
  bodyInit.def_readwrite("mass", &PfxBodyInit::mass, "kg; 0 makes a fixed body.")
      .def_readwrite("friction", &PfxBodyInit::friction, "Coefficient of friction.")
      .def_readwrite("restitution", &PfxBodyInit::restitution, "0 (no bounce) to 1.")
      .def_readwrite("motion_type", &PfxBodyInit::motionType, "MotionType when mass > 0.");

  py::class_<PyWorld>(m.attr("World"))
      .def(
          "add_body",
          [](PyWorld& w, py::object shapes, const PfxBodyInit& init) {
            std::vector<PyShape> parts;
            if (py::isinstance<PyShape>(shapes)) {
              parts.push_back(shapes.cast<PyShape>());
            } else {
              parts = shapes.cast<std::vector<PyShape>>();
            }
            std::vector<PfxShape> pfxShapes;
            for (const PyShape& part : parts) pfxShapes.push_back(part.shape);
            w.requireNoStateViews("add_body");
            PfxUInt32 id = 0;
            raiseIfError(pfxAddBody(w.world, pfxShapes.data(), PfxUInt32(pfxShapes.size()), init, &id),
                         "add_body");
            for (const PyShape& part : parts) {
              if (part.mesh) w.resources.push_back(part.mesh);
            }
            return id;
          },
          py::arg("shapes"), py::arg("init") = PfxBodyInit(),
          "Adds a body of one Shape or a list of them (a compound; their offsets should put\n"
          "the common centre of mass at the body's origin), with the inertia of a uniform\n"
          "solid of init.mass. Returns the body's id. Raises pfx.Error for NaN poses, negative\n"
          "mass, invalid shapes; the world is unchanged then.")
      .def(
          "body_mass",
          [](const PyWorld& w, PfxUInt32 id) {
            if (id >= w.world.getNumRigidBodies()) raiseIfError(PFX_ERR_OUT_OF_RANGE, "body id");
            return w.world.getRigidBody(id).getMass();
          },
          py::arg("body"), "The body's mass in kg.")
      .def(
          "remove_body",
          [](PyWorld& w, PfxUInt32 id) {
            w.requireNotCharacterBody(id);
            raiseIfError(w.world.removeRigidBody(id), "remove_body " + std::to_string(id));
          },
          py::arg("body"),
          "Removes the body with its joints, couplings and contacts. Its id is not given out\n"
          "again and every other id keeps its body; the state views stay valid (the slot\n"
          "stays, inert). Raises pfx.Error for an unknown or removed id, a body particles\n"
          "are pinned to, or a character's (CharacterController.remove removes those); the\n"
          "world is unchanged then.")
      .def(
          "has_body", [](const PyWorld& w, PfxUInt32 id) { return w.world.hasRigidBody(id); },
          py::arg("body"), "False for a removed id and for one never given.");
}

}  // namespace pfx::python
