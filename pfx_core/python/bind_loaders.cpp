// The loaders: URDF robots, scene files (pfx XML and SDFormat), OctoMaps and mesh files
// (as convex hulls and large meshes). A model is kept by the world, whose bodies point into
// its meshes; its Python object names bodies and joints until the world is emptied.
#include <algorithm>

#include <pybind11/stl.h>

#include "pfx/loaders/pfx_mesh_loader.h"
#include "pfx/loaders/pfx_octomap_loader.h"
#include "pfx/loaders/pfx_scene_loader.h"
#include "pfx/loaders/pfx_urdf_loader.h"
#include "pfx_python.h"

namespace pfx::python {

namespace {

using UrdfModel = PyLoaded<PfxUrdfModel>;
using SceneModel = PyLoaded<PfxSceneModel>;
using Octomap = PyLoaded<PfxOctomap>;

// Runs a loader on the world and keeps its model with the world on success.
template <typename Model, typename Load>
PyLoaded<Model> loadInto(PyWorld& w, const char* what, Load load) {
  w.requireNoStateViews(what);
  auto model = std::make_shared<Model>();
  std::string message;
  raiseIfError(load(*model, message), message);
  w.resources.push_back(model);
  return {model, &w, w.generation};
}

PfxUInt32 urdfJointIndex(const PfxUrdfModel& model, py::handle joint) {
  if (py::isinstance<py::str>(joint)) {
    const std::string name = joint.cast<std::string>();
    const PfxInt32 index = pfxFindUrdfJoint(model, name);
    if (index < 0) raiseIfError(PFX_ERR_OUT_OF_RANGE, "no URDF joint '" + name + "'");
    return PfxUInt32(index);
  }
  return joint.cast<PfxUInt32>();
}

py::tuple poseTuple(const PfxTransform3& pose) {
  const PfxVector3 position = pose.translation();
  const PfxQuat orientation(pose.rotation());
  return py::make_tuple(fromVector3(position), fromQuat(orientation));
}

void bindUrdfParam(py::module_& m) {
  py::class_<PfxUrdfLoadParam> param(m, "UrdfLoadParam", "PfxUrdfLoadParam: how a robot is loaded.");
  defKeywordInit(param, "Any field as a keyword; the rest keep pfx's defaults.");
  defVector3(param, "root_position", &PfxUrdfLoadParam::rootPosition, "World pose of the root.");
  defQuat(param, "root_orientation", &PfxUrdfLoadParam::rootOrientation, "(x, y, z, w).");
  param.def_readwrite("place_above_ground", &PfxUrdfLoadParam::placeAboveGround,
                      "Lift the robot so its lowest point is ground_clearance above the ground.")
      .def_readwrite("ground_height", &PfxUrdfLoadParam::groundHeight, "z of the ground (m).")
      .def_readwrite("ground_clearance", &PfxUrdfLoadParam::groundClearance, "m.")
      .def_readwrite("fixed_base", &PfxUrdfLoadParam::fixedBase, "Bolt the root to the world.")
      .def_readwrite("lump_fixed_joints", &PfxUrdfLoadParam::lumpFixedJoints,
                     "Merge links joined by fixed joints into one body.")
      .def_readwrite("collapse_massless_chains", &PfxUrdfLoadParam::collapseMasslessChains,
                     "Turn chains through massless links into one multi-axis joint.")
      .def_readwrite("disable_self_collision", &PfxUrdfLoadParam::disableSelfCollision,
                     "The robot's links never collide with each other.")
      .def_readwrite("self_collision_group", &PfxUrdfLoadParam::selfCollisionGroup,
                     "Contact filter bit of the robot (with disable_self_collision).")
      .def_readwrite("friction", &PfxUrdfLoadParam::friction, "Of every link.")
      .def_readwrite("restitution", &PfxUrdfLoadParam::restitution, "Of every link.")
      .def_readwrite("package_root", &PfxUrdfLoadParam::packageRoot,
                     "Folder that package:// URIs resolve in.")
      .def_readwrite("allow_missing_meshes", &PfxUrdfLoadParam::allowMissingMeshes,
                     "Leave out collision meshes whose files are missing, with a warning.");
}

void bindUrdfModel(py::module_& m) {
  py::class_<PfxUrdfJoint>(m, "UrdfJoint", "A joint of the URDF file and what it became.")
      .def_readonly("name", &PfxUrdfJoint::name, "As in the file.")
      .def_readonly("parent_link", &PfxUrdfJoint::parentLink, "Parent link's name.")
      .def_readonly("child_link", &PfxUrdfJoint::childLink, "Child link's name.")
      .def_property_readonly(
          "joint_id",
          [](const PfxUrdfJoint& j) {
            return j.jointId == kPfxUrdfNoJoint ? py::object(py::none()) : py::int_(j.jointId);
          },
          "World joint id carrying it, None for lumped or fixed joints.")
      .def_readonly("axis", &PfxUrdfJoint::axis, "Axis of the world joint (0..5).")
      .def_readonly("lower_limit", &PfxUrdfJoint::lowerLimit, "rad or m.")
      .def_readonly("upper_limit", &PfxUrdfJoint::upperLimit, "rad or m.")
      .def_readonly("effort_limit", &PfxUrdfJoint::effortLimit, "N or N m; 0: none given.")
      .def_readonly("velocity_limit", &PfxUrdfJoint::velocityLimit, "0: none given.");

  py::class_<UrdfModel>(m, "UrdfModel", "A robot loaded by World.load_urdf.")
      .def_property_readonly("name", [](const UrdfModel& u) { return u.current().name; }, "The robot's name.")
      .def_property_readonly("fixed_base", [](const UrdfModel& u) { return u.current().fixedBase; }, "Whether the root link is fixed.")
      .def_property_readonly("warnings", [](const UrdfModel& u) { return u.current().warnings; }, "What the loader noted but accepted.")
      .def_property_readonly("first_body_id", [](const UrdfModel& u) { return u.current().firstBodyId; }, "First of the bodies the load added (contiguous).")
      .def_property_readonly("num_bodies", [](const UrdfModel& u) { return u.current().numBodies; }, "Bodies the load added.")
      .def_property_readonly("first_joint_id", [](const UrdfModel& u) { return u.current().firstJointId; }, "First of the joints the load added (contiguous).")
      .def_property_readonly("num_joints", [](const UrdfModel& u) { return u.current().numJoints; }, "World joints the load added.")
      .def_property_readonly(
          "joints", [](const UrdfModel& u) { return u.current().joints; },
          "UrdfJoint of every joint in file order.")
      .def_property_readonly(
          "link_bodies",
          [](const UrdfModel& u) {
            py::dict links;
            for (const PfxUrdfLink& link : u.current().links) links[py::str(link.name)] = link.bodyId;
            return links;
          },
          "Link name -> id of the body carrying it (lumped links share one).")
      .def(
          "joint_states",
          [](const UrdfModel& u) {
            std::vector<double> positions, velocities;
            pfxGetUrdfJointStates(u.owner->world, u.current(), positions, velocities);
            return py::make_tuple(py::array_t<double>(positions.size(), positions.data()),
                                  py::array_t<double>(velocities.size(), velocities.data()));
          },
          "(positions, velocities) of every joint in file order (rad or m, and per second).")
      .def(
          "link_pose",
          [](const UrdfModel& u, const std::string& name) {
            const PfxInt32 index = pfxFindUrdfLink(u.current(), name);
            if (index < 0) raiseIfError(PFX_ERR_OUT_OF_RANGE, "no URDF link '" + name + "'");
            return poseTuple(pfxGetUrdfLinkPose(u.owner->world, u.current().links[index]));
          },
          py::arg("link"), "(position, orientation) of a link in the world.")
      .def(
          "set_joint_command",
          [](const UrdfModel& u, py::handle joint, PfxJointDrive drive, PfxFloat target,
             PfxFloat maxForce) {
            const PfxUrdfModel& model = u.current();
            std::string note;
            raiseIfError(pfxSetUrdfJointCommand(u.owner->world, model, urdfJointIndex(model, joint),
                                                drive, target, maxForce, &note),
                         "set_joint_command");
            return note;
          },
          py::arg("joint"), py::arg("drive"), py::arg("target") = 0, py::arg("max_force") = 0,
          "A motor command on a joint (name or index): JointDrive.POSITION or VELOCITY and a\n"
          "target cut to the joint's limits, or JointDrive.NONE. Returns a note when cut.");
}

void bindScene(py::module_& m) {
  py::class_<SceneModel>(m, "SceneModel", "A scene loaded by World.load_scene.")
      .def_property_readonly("warnings", [](const SceneModel& s) { return s.current().warnings; }, "What the loader noted but accepted.")
      .def_property_readonly("first_body_id", [](const SceneModel& s) { return s.current().firstBodyId; }, "First of the bodies the load added (contiguous).")
      .def_property_readonly("num_bodies", [](const SceneModel& s) { return s.current().numBodies; }, "Bodies the load added.")
      .def_property_readonly("num_joints", [](const SceneModel& s) { return s.current().numJoints; }, "Joints the load added.")
      .def_property_readonly(
          "bodies",
          [](const SceneModel& s) {
            py::dict bodies;
            for (const PfxSceneBody& body : s.current().bodies) bodies[py::str(body.name)] = body.bodyId;
            return bodies;
          },
          "Body name (SDF: model::link) -> body id.")
      .def_property_readonly(
          "joints",
          [](const SceneModel& s) {
            py::dict joints;
            for (const PfxSceneJoint& joint : s.current().joints) {
              joints[py::str(joint.name)] =
                  joint.jointId == kPfxSceneNone ? py::object(py::none()) : py::int_(joint.jointId);
            }
            return joints;
          },
          "Joint name -> world joint id (None when it became none).");

  py::class_<Octomap>(m, "Octomap", "An OctoMap loaded by World.load_octomap.")
      .def_property_readonly("body_id", [](const Octomap& o) { return o.current().bodyId; }, "Id of the map's fixed body.")
      .def_property_readonly("num_occupied_voxels",
                             [](const Octomap& o) { return o.current().numOccupiedVoxels; }, "Occupied cells at the finest resolution.")
      .def_property_readonly("resolution", [](const Octomap& o) { return o.current().resolution; }, "Finest cell size (m).");
}

void bindMeshes(py::module_& m) {
  m.def(
      "load_mesh",
      [](const std::string& path, py::handle scale) {
        PfxTriangleMesh mesh;
        std::string message;
        raiseIfError(pfxLoadMeshFile(path, toVector3(scale, "scale"), mesh, &message), message);
        const py::ssize_t numVertices = mesh.vertices.size() / 3, numTriangles = mesh.triangles.size() / 3;
        auto vertices = newArray<PfxFloat>(numVertices, 3);
        auto triangles = newArray<PfxUInt32>(numTriangles, 3);
        std::copy(mesh.vertices.begin(), mesh.vertices.end(), vertices.mutable_data());
        std::copy(mesh.triangles.begin(), mesh.triangles.end(), triangles.mutable_data());
        return py::make_tuple(vertices, triangles);
      },
      py::arg("path"), py::arg("scale") = py::make_tuple(1, 1, 1),
      "Reads a mesh file (STL, Collada, OBJ, ... through assimp): (vertices (n, 3), triangles\n"
      "(m, 3)).");

  py::class_<PfxConvexMesh, std::shared_ptr<PfxConvexMesh>>(m.attr("ConvexMesh"))
      .def_static(
          "hull",
          [](py::handle vertices) {
            const auto points = toRows(vertices, 3, "vertices");
            PfxTriangleMesh mesh;
            mesh.vertices.assign(points.data(), points.data() + points.size());
            PfxConvexMesh* hull = pfxNewConvexMesh();
            if (!hull) throw std::bad_alloc();
            std::shared_ptr<PfxConvexMesh> owned(hull, &pfxDeleteConvexMesh);
            std::string message;
            raiseIfError(pfxCreateConvexHull(mesh, *owned, &message), message);
            return owned;
          },
          py::arg("vertices"),
          "The convex hull (qhull) of points (n, 3), cut to 34 corners when it has more.");

  py::class_<PfxLargeTriMesh, std::shared_ptr<PfxLargeTriMesh>>(
      m, "LargeTriMesh", "A triangle mesh of any size for fixed bodies (terrain, rooms).")
      .def(py::init([](py::handle vertices, py::handle triangles, PfxUInt32 flags, PfxFloat thickness) {
             const auto points = toRows(vertices, 3, "vertices");
             const auto corners =
                 py::array_t<PfxUInt32, py::array::c_style | py::array::forcecast>::ensure(triangles);
             if (!corners || corners.ndim() != 2 || corners.shape(1) != 3) {
               throw py::value_error("triangles must be an integer array of shape (m, 3)");
             }
             PfxTriangleMesh mesh;
             mesh.vertices.assign(points.data(), points.data() + points.size());
             mesh.triangles.assign(corners.data(), corners.data() + corners.size());
             PfxLargeTriMesh* large = pfxNewLargeTriMesh();
             if (!large) throw std::bad_alloc();
             std::shared_ptr<PfxLargeTriMesh> owned(large, &pfxDeleteLargeTriMesh);
             std::string message;
             raiseIfError(pfxCreateLargeTriMeshFromMesh(mesh, flags, *owned, &message, thickness),
                          message);
             return owned;
           }),
           py::arg("vertices"), py::arg("triangles"), py::arg("flags") = PFX_MESH_FLAG_USE_BVH,
           py::arg("thickness") = PFX_MESH_DEFAULT_THICKNESS,
           "From vertices (n, 3) and triangles (m, 3); flags are MESH_FLAG_*.");
  m.attr("MESH_FLAG_USE_BVH") = PFX_MESH_FLAG_USE_BVH;
  m.attr("MESH_FLAG_USE_QUANTIZED") = PFX_MESH_FLAG_USE_QUANTIZED;
  m.attr("MESH_FLAG_HIGH_QUALITY") = PFX_MESH_FLAG_HIGH_QUALITY;

  py::class_<PyShape>(m.attr("Shape"))
      .def_static(
          "large_mesh",
          [](std::shared_ptr<PfxLargeTriMesh> mesh, py::handle p, py::handle q) {
            PyShape shape;
            shape.shape.reset();
            shape.shape.setLargeTriMesh(mesh.get());
            shape.shape.setOffsetPosition(toVector3(p, "offset_position"));
            shape.shape.setOffsetOrientation(toQuat(q, "offset_orientation"));
            shape.mesh = std::move(mesh);
            return shape;
          },
          py::arg("mesh"), py::arg("offset_position") = py::make_tuple(0, 0, 0),
          py::arg("offset_orientation") = py::make_tuple(0, 0, 0, 1),
          "A LargeTriMesh, for a fixed body (mass 0); the body keeps the mesh alive.");
}

}  // namespace

void bindLoaders(py::module_& m) {
  bindUrdfParam(m);
  bindUrdfModel(m);
  bindScene(m);
  bindMeshes(m);
  py::class_<PyWorld>(m.attr("World"))
      .def(
          "load_urdf",
          [](PyWorld& w, const std::string& path, const PfxUrdfLoadParam& param) {
            return loadInto<PfxUrdfModel>(w, "load_urdf", [&](PfxUrdfModel& model, std::string& msg) {
              return pfxLoadUrdfFile(w.world, path, param, model, &msg);
            });
          },
          py::arg("path"), py::arg("param") = PfxUrdfLoadParam(), py::keep_alive<0, 1>(),
          "Loads a URDF robot; returns its UrdfModel. URDF worlds are Z up: give the world\n"
          "gravity (0, 0, -9.81). Raises pfx.Error naming the file, element and reason.")
      .def(
          "load_urdf_string",
          [](PyWorld& w, const std::string& xml, const std::string& basePath,
             const PfxUrdfLoadParam& param) {
            return loadInto<PfxUrdfModel>(w, "load_urdf_string", [&](PfxUrdfModel& model, std::string& msg) {
              return pfxLoadUrdfString(w.world, xml, basePath, param, model, &msg);
            });
          },
          py::arg("xml"), py::arg("base_path") = "", py::arg("param") = PfxUrdfLoadParam(),
          py::keep_alive<0, 1>(), "As load_urdf, from text; meshes resolve from base_path.")
      .def(
          "load_scene",
          [](PyWorld& w, const std::string& path, bool applyPhysics) {
            PfxSceneLoadParam param;
            param.applyPhysics = applyPhysics;
            return loadInto<PfxSceneModel>(w, "load_scene", [&](PfxSceneModel& model, std::string& msg) {
              return pfxLoadSceneFile(w.world, path, param, model, &msg);
            });
          },
          py::arg("path"), py::arg("apply_physics") = true, py::keep_alive<0, 1>(),
          "Loads a scene file (pfx XML or an SDFormat world); its physics replace the world's\n"
          "parameters when the world is empty and apply_physics. Returns its SceneModel.")
      .def(
          "load_octomap",
          [](PyWorld& w, const std::string& path, py::handle position, py::handle orientation,
             PfxFloat friction) {
            PfxOctomapLoadParam param;
            param.position = toVector3(position, "position");
            param.orientation = toQuat(orientation, "orientation");
            param.friction = friction;
            return loadInto<PfxOctomap>(w, "load_octomap", [&](PfxOctomap& map, std::string& msg) {
              return pfxLoadOctomapFile(w.world, path, param, map, &msg);
            });
          },
          py::arg("path"), py::arg("position") = py::make_tuple(0, 0, 0),
          py::arg("orientation") = py::make_tuple(0, 0, 0, 1), py::arg("friction") = 0.6,
          py::keep_alive<0, 1>(),
          "Adds an OctoMap's (.bt, .ot) occupied cells as one fixed body; returns its Octomap.");
}

}  // namespace pfx::python
