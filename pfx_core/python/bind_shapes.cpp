// Shapes: the four geometric ones by value, convex meshes from a triangle list, and (with the
// loaders) large triangle meshes, each placed in its body by an offset pose.
#include <algorithm>

#include "pfx_python.h"

namespace pfx::python {

namespace {

std::shared_ptr<PfxConvexMesh> newConvexMesh() {
  PfxConvexMesh* mesh = pfxNewConvexMesh();
  if (!mesh) throw std::bad_alloc();
  return std::shared_ptr<PfxConvexMesh>(mesh, &pfxDeleteConvexMesh);
}

// A convex mesh from vertices (n, 3) and triangles (m, 3) through pfxCreateConvexMesh.
std::shared_ptr<PfxConvexMesh> convexMeshFromTriangles(py::handle vertices, py::handle triangles) {
  const auto points = toRows(vertices, 3, "vertices");
  const auto corners =
      py::array_t<PfxUInt32, py::array::c_style | py::array::forcecast>::ensure(triangles);
  if (!corners || corners.ndim() != 2 || corners.shape(1) != 3) {
    throw py::value_error("triangles must be an integer array of shape (m, 3)");
  }
  std::vector<PfxUInt16> indices(corners.size());
  for (py::ssize_t i = 0; i < corners.size(); ++i) {
    // An index beyond 16 bits cannot name one of a convex mesh's 34 vertices either.
    indices[i] = PfxUInt16(std::min<PfxUInt32>(corners.data()[i], 0xffff));
  }
  std::shared_ptr<PfxConvexMesh> mesh = newConvexMesh();
  raiseIfError(pfxCreateConvexMesh(*mesh, points.data(), PfxUInt32(points.shape(0)),
                                   indices.data(), PfxUInt32(indices.size())),
               "pfxCreateConvexMesh");
  return mesh;
}

template <typename Geometry>
PyShape makeShape(const Geometry& geometry, py::handle position, py::handle orientation) {
  PyShape shape;
  shape.shape = pfxMakeShape(geometry);
  shape.shape.setOffsetPosition(toVector3(position, "offset_position"));
  shape.shape.setOffsetOrientation(toQuat(orientation, "offset_orientation"));
  return shape;
}

const char* const kOffsetDoc =
    "offset_position and offset_orientation place the shape in its body's frame.";

}  // namespace

void bindShapes(py::module_& m) {
  py::class_<PfxConvexMesh, std::shared_ptr<PfxConvexMesh>>(
      m, "ConvexMesh",
      "A closed convex polyhedron of at most 64 triangles and 34 vertices (pfxCreateConvexMesh).")
      .def(py::init(&convexMeshFromTriangles), py::arg("vertices"), py::arg("triangles"),
           "From vertices (n, 3) and triangles (m, 3) of vertex indices; either winding.\n"
           "Raises pfx.InvalidValueError for open, non-convex, degenerate or too large meshes.")
      .def_property_readonly(
          "vertices",
          [](const PfxConvexMesh& mesh) {
            auto out = newArray<PfxFloat>(mesh.m_numVerts, 3);
            for (PfxUInt32 i = 0; i < mesh.m_numVerts; ++i) {
              std::copy(mesh.m_verts[i].data(), mesh.m_verts[i].data() + 3,
                        out.mutable_data(i, 0));
            }
            return out;
          },
          "The welded vertices, (n, 3).")
      .def_property_readonly(
          "num_faces", [](const PfxConvexMesh& mesh) { return int(mesh.m_numFaces); },
          "Planar polygons after coplanar triangles were merged.");

  py::class_<PyShape>(m, "Shape",
                      "One collision shape and its pose in the body. Make one with\n"
                      "Shape.sphere, box, capsule, cylinder or convex_mesh.")
      .def_static(
          "sphere",
          [](PfxFloat radius, py::handle p, py::handle q) {
            return makeShape(PfxSphere(radius), p, q);
          },
          py::arg("radius"), py::arg("offset_position") = py::make_tuple(0, 0, 0),
          py::arg("offset_orientation") = py::make_tuple(0, 0, 0, 1),
          (std::string("A sphere of the given radius (m). ") + kOffsetDoc).c_str())
      .def_static(
          "box",
          [](py::handle half, py::handle p, py::handle q) {
            return makeShape(PfxBox(toVector3(half, "half_extents")), p, q);
          },
          py::arg("half_extents"), py::arg("offset_position") = py::make_tuple(0, 0, 0),
          py::arg("offset_orientation") = py::make_tuple(0, 0, 0, 1),
          (std::string("A box of half extents (x, y, z) in m. ") + kOffsetDoc).c_str())
      .def_static(
          "capsule",
          [](PfxFloat halfLength, PfxFloat radius, py::handle p, py::handle q) {
            return makeShape(PfxCapsule(halfLength, radius), p, q);
          },
          py::arg("half_length"), py::arg("radius"),
          py::arg("offset_position") = py::make_tuple(0, 0, 0),
          py::arg("offset_orientation") = py::make_tuple(0, 0, 0, 1),
          (std::string("A capsule along the local X axis. ") + kOffsetDoc).c_str())
      .def_static(
          "cylinder",
          [](PfxFloat halfLength, PfxFloat radius, py::handle p, py::handle q) {
            return makeShape(PfxCylinder(halfLength, radius), p, q);
          },
          py::arg("half_length"), py::arg("radius"),
          py::arg("offset_position") = py::make_tuple(0, 0, 0),
          py::arg("offset_orientation") = py::make_tuple(0, 0, 0, 1),
          (std::string("A cylinder along the local X axis. ") + kOffsetDoc).c_str())
      .def_static(
          "convex_mesh",
          [](std::shared_ptr<PfxConvexMesh> mesh, py::handle p, py::handle q) {
            PyShape shape = makeShape(mesh.get(), p, q);
            shape.mesh = std::move(mesh);
            return shape;
          },
          py::arg("mesh"), py::arg("offset_position") = py::make_tuple(0, 0, 0),
          py::arg("offset_orientation") = py::make_tuple(0, 0, 0, 1),
          (std::string("A convex mesh; bodies made of it keep it alive. ") + kOffsetDoc).c_str())
      .def_property_readonly(
          "type",
          [](const PyShape& s) {
            static const char* const kNames[] = {"sphere",   "box",         "capsule",
                                                 "cylinder", "convex_mesh", "large_mesh"};
            return std::string(kNames[s.shape.getType()]);
          },
          "'sphere', 'box', 'capsule', 'cylinder', 'convex_mesh' or 'large_mesh'.")
      .def_property_readonly(
          "offset_position", [](const PyShape& s) { return fromVector3(s.shape.getOffsetPosition()); },
          "Position in the body's frame.")
      .def_property_readonly(
          "offset_orientation",
          [](const PyShape& s) { return fromQuat(s.shape.getOffsetOrientation()); },
          "Orientation in the body's frame (x, y, z, w).");
}

}  // namespace pfx::python
