// Queries on the world as it is: rays (one, or a batch from numpy arrays), the contact points
// of the last step, and the contacts a shape placed anywhere would have.
#include <algorithm>

#include "pfx_python.h"

namespace pfx::python {

namespace {

// Numpy columns of ray results: one row per ray.
struct RayColumns {
  explicit RayColumns(py::ssize_t n)
      : hit(n), fraction(n), point(newArray<PfxFloat>(n, 3)), normal(newArray<PfxFloat>(n, 3)), body(n),
        shape(n), triangle(n), particleGroup(n), particle(n) {}

  void set(py::ssize_t i, const PfxRayOutput& out) {
    hit.mutable_at(i) = out.m_contactFlag;
    fraction.mutable_at(i) = out.m_variable;
    std::copy(out.m_contactPoint.data(), out.m_contactPoint.data() + 3, point.mutable_data(i, 0));
    std::copy(out.m_contactNormal.data(), out.m_contactNormal.data() + 3, normal.mutable_data(i, 0));
    // A particle's hit names no body: its group and particle instead.
    const bool bodyHit = out.m_contactFlag && out.m_objectId != PFX_RAY_NO_OBJECT;
    body.mutable_at(i) = bodyHit ? PfxInt64(out.m_objectId) : -1;
    shape.mutable_at(i) = bodyHit ? PfxInt32(out.m_shapeId) : -1;
    triangle.mutable_at(i) =
        out.m_triangleIndex == PFX_RAY_NO_TRIANGLE ? -1 : PfxInt64(out.m_triangleIndex);
    particleGroup.mutable_at(i) =
        out.m_particleGroupId == PFX_RAY_NO_OBJECT ? -1 : PfxInt64(out.m_particleGroupId);
    particle.mutable_at(i) =
        out.m_particleIndex == PFX_RAY_NO_OBJECT ? -1 : PfxInt64(out.m_particleIndex);
  }

  py::dict toDict() const {
    py::dict d;
    d["hit"] = hit;
    d["fraction"] = fraction;
    d["point"] = point;
    d["normal"] = normal;
    d["body"] = body;
    d["shape"] = shape;
    d["triangle"] = triangle;
    d["particle_group"] = particleGroup;
    d["particle"] = particle;
    return d;
  }

  py::array_t<bool> hit;
  py::array_t<PfxFloat> fraction, point, normal;
  py::array_t<PfxInt64> body;
  py::array_t<PfxInt32> shape;
  py::array_t<PfxInt64> triangle, particleGroup, particle;
};

const char* const kRayResultDoc =
    "Returns a dict of numpy arrays, one row per ray: hit (bool), fraction (of the ray's\n"
    "length, 1 on a miss), point and normal (n, 3), body (-1 on a miss or a particle's hit),\n"
    "shape (index in the body, else -1), triangle (of a large mesh or a cloth, else -1),\n"
    "particle_group and particle (a particle group's hit, else -1).";

PfxRayInput makeRay(const PfxFloat* start, const PfxFloat* direction, PfxUInt32 filterSelf,
                    PfxUInt32 filterTarget) {
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = PfxVector3(start[0], start[1], start[2]);
  ray.m_direction = PfxVector3(direction[0], direction[1], direction[2]);
  ray.m_contactFilterSelf = filterSelf;
  ray.m_contactFilterTarget = filterTarget;
  return ray;
}

py::dict castRays(PyWorld& w, py::handle starts, py::handle directions, PfxUInt32 filterSelf,
                  PfxUInt32 filterTarget) {
  const auto from = toRows(starts, 3, "starts");
  const auto along = toRows(directions, 3, "directions");
  if (from.shape(0) != along.shape(0)) {
    throw py::value_error("starts and directions must have as many rows");
  }
  const py::ssize_t n = from.shape(0);
  std::vector<PfxRayInput> rays(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    rays[i] = makeRay(from.data(i, 0), along.data(i, 0), filterSelf, filterTarget);
  }
  std::vector<PfxRayOutput> hits(n);
  PfxInt32 err = PFX_OK;
  {
    py::gil_scoped_release release;
    err = w.world.castRays(rays.data(), hits.data(), PfxUInt32(n));
  }
  raiseIfError(err, "cast_rays");
  RayColumns columns(n);
  for (py::ssize_t i = 0; i < n; ++i) columns.set(i, hits[i]);
  return columns.toDict();
}

// Every contact point of the last step's pairs, one row per point.
py::dict contacts(const PyWorld& w) {
  const PfxWorld& world = w.world;
  py::ssize_t n = 0;
  for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
    n += world.getContactManifold(world.getContactPair(i)).getNumContacts();
  }
  py::array_t<PfxInt64> bodyA(n), bodyB(n);
  py::array_t<PfxFloat> pointA(newArray<PfxFloat>(n, 3)), pointB(newArray<PfxFloat>(n, 3)),
      normal(newArray<PfxFloat>(n, 3)), distance(n), impulse(n);
  py::ssize_t row = 0;
  for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
    const PfxContactManifold& manifold = world.getContactManifold(world.getContactPair(i));
    const PfxTransform3 a = world.getRigidState(manifold.getRigidBodyIdA()).getTransform();
    const PfxTransform3 b = world.getRigidState(manifold.getRigidBodyIdB()).getTransform();
    for (PfxUInt32 k = 0; k < manifold.getNumContacts(); ++k, ++row) {
      const PfxContactPoint& point = manifold.getContactPoint(k);
      bodyA.mutable_at(row) = manifold.getRigidBodyIdA();
      bodyB.mutable_at(row) = manifold.getRigidBodyIdB();
      const PfxVector3 onA = a * point.m_localPointA, onB = b * point.m_localPointB;
      std::copy(onA.data(), onA.data() + 3, pointA.mutable_data(row, 0));
      std::copy(onB.data(), onB.data() + 3, pointB.mutable_data(row, 0));
      std::copy(point.getNormal().data(), point.getNormal().data() + 3, normal.mutable_data(row, 0));
      distance.mutable_at(row) = point.m_distance;
      impulse.mutable_at(row) = point.m_constraintRow[0].m_accumImpulse;
    }
  }
  py::dict d;
  d["body_a"] = bodyA;
  d["body_b"] = bodyB;
  d["point_a"] = pointA;
  d["point_b"] = pointB;
  d["normal"] = normal;
  d["distance"] = distance;
  d["impulse"] = impulse;
  return d;
}

py::dict queryContacts(PyWorld& w, const PyShape& shape, py::handle position,
                       py::handle orientation, PfxFloat threshold, PfxUInt32 maxContacts,
                       PfxUInt32 ignoreBody) {
  PfxCollidable collidable;
  collidable.reset();
  raiseIfError(collidable.addShape(shape.shape), "query shape");
  raiseIfError(collidable.finish(), "query shape");
  PfxContactQueryInput query;
  query.collidable = &collidable;
  query.transform =
      pfxMakeTransform(toQuat(orientation, "orientation"), toVector3(position, "position"));
  query.contactThreshold = threshold;
  query.ignoreRigidBodyId = ignoreBody;
  std::vector<PfxQueryContact> found(maxContacts);
  PfxQueryContactsResult result;
  const ErrorDetailWatch watch;
  watch.raiseIfError(w.world.queryContacts(query, found.data(), maxContacts, result));
  const py::ssize_t n = result.numContacts;
  py::array_t<PfxInt64> body(n);
  py::array_t<PfxFloat> pointOnShape(newArray<PfxFloat>(n, 3)), pointOnBody(newArray<PfxFloat>(n, 3)),
      normal(newArray<PfxFloat>(n, 3)), distance(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    const PfxContactCandidate& c = found[i].m_contact;
    body.mutable_at(i) = found[i].m_rigidBodyId;
    std::copy(c.m_pointA.data(), c.m_pointA.data() + 3, pointOnShape.mutable_data(i, 0));
    std::copy(c.m_pointB.data(), c.m_pointB.data() + 3, pointOnBody.mutable_data(i, 0));
    std::copy(c.m_normal.data(), c.m_normal.data() + 3, normal.mutable_data(i, 0));
    distance.mutable_at(i) = c.m_distance;
  }
  py::dict d;
  d["body"] = body;
  d["point_on_shape"] = pointOnShape;
  d["point_on_body"] = pointOnBody;
  d["normal"] = normal;
  d["distance"] = distance;
  d["truncated"] = result.truncated;
  return d;
}

}  // namespace

void bindQueries(py::module_& m) {
  py::class_<PyWorld>(m.attr("World"))
      .def("cast_rays", &castRays, py::arg("starts"), py::arg("directions"),
           py::arg("filter_self") = 0xffffffffu, py::arg("filter_target") = 0xffffffffu,
           (std::string("The closest hit of each ray from starts (n, 3) along directions (n, 3)\n"
                        "(end minus start), in one batch on the world's threads (castRays). ") +
            kRayResultDoc)
               .c_str())
      .def(
          "cast_ray",
          [](PyWorld& w, py::handle start, py::handle direction, PfxUInt32 filterSelf,
             PfxUInt32 filterTarget) {
            const PfxVector3 from = toVector3(start, "start"), along = toVector3(direction, "direction");
            const PfxRayInput ray = makeRay(from.data(), along.data(), filterSelf, filterTarget);
            PfxRayOutput hit;
            raiseIfError(w.world.castRay(ray, hit), "cast_ray");
            RayColumns columns(1);
            columns.set(0, hit);
            return columns.toDict();
          },
          py::arg("start"), py::arg("direction"), py::arg("filter_self") = 0xffffffffu,
          py::arg("filter_target") = 0xffffffffu,
          (std::string("One ray through castRay. ") + kRayResultDoc).c_str())
      .def("contacts", &contacts,
           "The contact points of the last step (sleeping pairs included), one row per point:\n"
           "body_a, body_b, point_a and point_b (world, on each surface), normal (from A to B),\n"
           "distance (negative: overlap) and impulse (normal, N s). A copy.")
      .def("query_contacts", &queryContacts, py::arg("shape"), py::arg("position"),
           py::arg("orientation") = py::make_tuple(0, 0, 0, 1), py::arg("threshold") = 0,
           py::arg("max_contacts") = 64, py::arg("ignore_body") = PFX_QUERY_IGNORE_NONE,
           "The contacts one Shape at a pose would have with the bodies, without adding it:\n"
           "body, point_on_shape, point_on_body, normal (shape to body), distance (negative:\n"
           "overlap), and truncated (more than max_contacts were found).");
}

}  // namespace pfx::python
