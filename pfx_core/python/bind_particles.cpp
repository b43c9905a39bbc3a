// Particle groups (ropes, cloths, hair; pfx_particle_group.h): built with
// ParticleGroupBuilder, added to and removed from a world, their positions read as numpy
// views of the world's own particles.
#include "pfx_python.h"

namespace pfx::python {

namespace {

using Material = PfxParticleGroupBuilder::Material;

const PfxParticleGroup& groupOf(const PyWorld& w, PfxUInt32 id) {
  const PfxParticleGroup* group = w.world.getParticleGroup(id);
  if (!group) raiseIfError(PFX_ERR_OUT_OF_RANGE, "no particle group " + std::to_string(id));
  return *group;
}

void bindMaterial(py::module_& m) {
  py::class_<Material> material(m, "ParticleMaterial",
                                "PfxParticleGroupBuilder::Material: mass, radius, friction,\n"
                                "compliances and contact filters of the particles a builder adds.");
  defKeywordInit(material, "Any field as a keyword; the rest keep pfx's defaults.");
  material.def_readwrite("particle_mass", &Material::particleMass, "kg per particle.")
      .def_readwrite("radius", &Material::radius, "m.")
      .def_readwrite("friction", &Material::friction, "Coefficient of friction.")
      .def_readwrite("stretch_compliance", &Material::stretchCompliance, "m/N (0: inextensible).")
      .def_readwrite("bend_compliance", &Material::bendCompliance,
                     "Rope rad/(N m), cloth m/N; negative adds no bending constraints.")
      .def_readwrite("contact_filter_self", &Material::contactFilterSelf, "Contact filter bits.")
      .def_readwrite("contact_filter_target", &Material::contactFilterTarget,
                     "Contact filter bits it touches.");
}

void bindBuilder(py::module_& m) {
  py::class_<PfxParticleGroupBuilder>(
      m, "ParticleGroupBuilder",
      "PfxParticleGroupBuilder: ropes and cloths with their constraints, and pins, to add to\n"
      "a world as one group (World.add_particle_group).")
      .def(py::init<>(), "An empty group.")
      .def(
          "add_rope",
          [](PfxParticleGroupBuilder& b, py::handle start, py::handle end, PfxUInt32 count,
             const Material& material) {
            if (count < 2) raiseIfError(PFX_ERR_INVALID_VALUE, "a rope needs 2 particles or more");
            return b.addRope(toVector3(start, "start"), toVector3(end, "end"), count, material);
          },
          py::arg("start"), py::arg("end"), py::arg("count"), py::arg("material") = Material(),
          "A straight rope of count particles from start to end; returns its first particle.")
      .def(
          "add_cloth",
          [](PfxParticleGroupBuilder& b, py::handle corner, py::handle edgeU, py::handle edgeV,
             PfxUInt32 numU, PfxUInt32 numV, const Material& material) {
            if (numU < 2 || numV < 2) {
              raiseIfError(PFX_ERR_INVALID_VALUE, "a cloth needs 2 particles or more each way");
            }
            return b.addCloth(toVector3(corner, "corner"), toVector3(edgeU, "edge_u"),
                              toVector3(edgeV, "edge_v"), numU, numV, material);
          },
          py::arg("corner"), py::arg("edge_u"), py::arg("edge_v"), py::arg("num_u"),
          py::arg("num_v"), py::arg("material") = Material(),
          "A num_u x num_v cloth spanning edge_u and edge_v from corner (particle i + j *\n"
          "num_u), with its triangles; returns its first particle.")
      .def(
          "pin_to_world",
          [](PfxParticleGroupBuilder& b, PfxUInt32 particle) {
            if (particle >= b.particles.size()) {
              raiseIfError(PFX_ERR_OUT_OF_RANGE, "particle " + std::to_string(particle) + " of " +
                                                     std::to_string(b.particles.size()));
            }
            b.pinToWorld(particle);
          },
          py::arg("particle"), "Holds a particle where it is.")
      .def_property_readonly(
          "num_particles", [](const PfxParticleGroupBuilder& b) { return b.particles.size(); },
          "Particles added so far.")
      .def_readwrite("linear_damping", &PfxParticleGroupBuilder::linearDamping, "1/s.")
      .def_readwrite("iteration", &PfxParticleGroupBuilder::iteration,
                     "Solver iterations per sub-step.")
      .def_readwrite("self_collision", &PfxParticleGroupBuilder::selfCollision,
                     "Whether the group's particles collide with each other.");
}

}  // namespace

void bindParticles(py::module_& m) {
  bindMaterial(m);
  bindBuilder(m);
  py::class_<PyWorld>(m.attr("World"))
      .def(
          "add_particle_group",
          [](PyWorld& w, const PfxParticleGroupBuilder& builder) {
            PfxUInt32 id = 0;
            ErrorDetailWatch watch;
            watch.raiseIfError(w.world.addParticleGroup(builder.desc(), &id));
            return id;
          },
          py::arg("builder"),
          "Adds the builder's particles and constraints as a group (copied); returns its id,\n"
          "the lowest free one.")
      .def(
          "remove_particle_group",
          [](PyWorld& w, PfxUInt32 id) {
            groupOf(w, id);
            w.requireNoStateViews("remove_particle_group");
            raiseIfError(w.world.removeParticleGroup(id));
          },
          py::arg("group"), "Removes a group; its id becomes free.")
      .def_property_readonly(
          "particle_groups",
          [](const PyWorld& w) {
            py::list ids;
            for (PfxUInt32 id = 0; id < w.world.getParticleGroupCapacity(); ++id) {
              if (w.world.getParticleGroup(id)) ids.append(id);
            }
            return ids;
          },
          "Ids of the world's particle groups.")
      .def(
          "particle_positions",
          [](const py::object& self, PfxUInt32 id) {
            const PfxParticleGroup& group = groupOf(self.cast<PyWorld&>(), id);
            const void* first = group.particles.empty() ? nullptr : group.particles[0].m_position.data();
            return worldMemoryView(self, first,
                                   py::ssize_t(group.particles.size()), 3, sizeof(PfxParticle));
          },
          py::arg("group"),
          "Positions (n, 3) of a group's particles: a read-only view of the world's own memory\n"
          "(no copy) that shows every step; while it lives, remove_particle_group, initialize,\n"
          "load and truncate raise.")
      .def(
          "set_particle_position",
          [](PyWorld& w, PfxUInt32 id, PfxUInt32 particle, py::handle position) {
            raiseIfError(w.world.setParticlePosition(id, particle, toVector3(position, "position")),
                         "group " + std::to_string(id) + " particle " + std::to_string(particle));
          },
          py::arg("group"), py::arg("particle"), py::arg("position"),
          "Moves one particle (no velocity gained) and wakes its group.");
}

}  // namespace pfx::python
