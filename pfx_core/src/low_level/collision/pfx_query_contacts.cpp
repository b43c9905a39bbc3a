#include "pfx/low_level/collision/pfx_query_contacts.h"

#include <algorithm>
#include <limits>

#include "low_level/pfx_param_checks.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"

namespace pfx {

namespace {

constexpr PfxParamNames kQueryContactsAt = {"pfxQueryContacts", "PfxQueryContactsParam"};
constexpr double kQueryQuantizedMax = 65535.0;
constexpr double kQueryInfinity = std::numeric_limits<double>::infinity();

bool isRigid(const PfxTransform3& transform) {
  const PfxMatrix3 r = transform.linear();
  return pfxIsFinite(r) && pfxIsFinite(PfxVector3(transform.translation())) &&
         (r * r.transpose() - PfxMatrix3::Identity()).cwiseAbs().maxCoeff() < PfxFloat(1e-3) &&
         r.determinant() > 0;
}

PfxInt32 checkQuery(const PfxContactQueryInput& query) {
  if (!query.collidable || query.collidable->getNumShapes() == 0) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxQueryContacts: PfxContactQueryInput::collidable is null or empty");
  }
  for (PfxUInt32 i = 0; i < query.collidable->getNumShapes(); ++i) {
    if (query.collidable->getShape(i).getType() == kPfxShapeLargeTriMesh) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxQueryContacts: shape %u of the queried collidable is a large "
                            "mesh, which meets no other large mesh",
                            i);
    }
  }
  if (!isRigid(query.transform)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxQueryContacts: PfxContactQueryInput::transform is not a finite "
                          "rotation and translation");
  }
  return pfxCheckValue({"pfxQueryContacts", "PfxContactQueryInput"}, "contactThreshold",
                       query.contactThreshold,
                       query.contactThreshold >= 0 && pfxIsFinite(query.contactThreshold),
                       "finite and not negative");
}

PfxInt32 checkParam(const PfxQueryContactsParam& param) {
  if (!pfxIsFinite(param.rangeCenter) || !pfxIsFinite(param.rangeExtent) ||
      !(param.rangeExtent.minCoeff() > 0)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxQueryContacts: PfxQueryContactsParam::rangeCenter and rangeExtent "
                          "must be finite, the extent positive");
  }
  return pfxCheckRequired(kQueryContactsAt,
                          {{param.offsetRigidStates, "offsetRigidStates"},
                           {param.offsetCollidables, "offsetCollidables"},
                           {param.bvhNodes, "bvhNodes"},
                           {param.bvhProxies, "bvhProxies"}},
                          "numProxies", param.numProxies);
}

// The query's bounds in the cells of the proxies' grid, each side widened by one cell, as
// rays widen theirs, so that rounding never hides a body.
struct BoxInCells {
  double lo[3];
  double hi[3];
};

BoxInCells toCells(const PfxVector3& center, const PfxVector3& half,
                   const PfxQueryContactsParam& param) {
  BoxInCells box;
  for (int a = 0; a < 3; ++a) {
    const double extent = param.rangeExtent[a];
    const double cellsPerMetre = kQueryQuantizedMax / (2.0 * extent);
    const double origin = double(param.rangeCenter[a]) - extent;
    box.lo[a] = (double(center[a]) - double(half[a]) - origin) * cellsPerMetre - 1.0;
    box.hi[a] = (double(center[a]) + double(half[a]) - origin) * cellsPerMetre + 1.0;
  }
  return box;
}

// A side of a proxy clamped to the edge of the range stands for everything beyond it.
bool boxMeetsCells(const BoxInCells& box, const PfxUInt16 min[3], const PfxUInt16 max[3]) {
  for (int a = 0; a < 3; ++a) {
    const double lo = min[a] == 0 ? -kQueryInfinity : double(min[a]);
    const double hi = max[a] == 0xffff ? kQueryInfinity : double(max[a]);
    if (box.hi[a] < lo || box.lo[a] > hi) return false;
  }
  return true;
}

bool boxMeetsProxy(const BoxInCells& box, const PfxBroadphaseProxy& proxy) {
  const PfxUInt16 min[3] = {pfxGetXMin(proxy, 0), pfxGetXMin(proxy, 1), pfxGetXMin(proxy, 2)};
  const PfxUInt16 max[3] = {pfxGetXMax(proxy, 0), pfxGetXMax(proxy, 1), pfxGetXMax(proxy, 2)};
  return boxMeetsCells(box, min, max);
}

}  // namespace

PfxInt32 pfxQueryContacts(const PfxContactQueryInput& query, const PfxQueryContactsParam& param,
                          PfxQueryContact* out, PfxUInt32 maxContacts,
                          PfxQueryContactsResult& result) {
  if (const PfxInt32 err = checkQuery(query); err != PFX_OK) return err;
  if (const PfxInt32 err = checkParam(param); err != PFX_OK) return err;
  if (!out && maxContacts > 0)
    return pfxRejectNull(kQueryContactsAt, "out", "maxContacts", maxContacts);

  PfxQueryContactsResult found;
  if (param.numProxies == 0) {
    result = found;
    return PFX_OK;
  }
  PfxVector3 center, half;
  query.collidable->getWorldAabb(query.transform, center, half);
  half += PfxVector3::Constant(query.contactThreshold);
  const BoxInCells box = toCells(center, half, param);

  const auto testBody = [&](const PfxBroadphaseProxy& proxy) {
    const PfxUInt32 id = pfxGetObjectId(proxy);
    if (id == query.ignoreRigidBodyId ||
        !pfxContactFiltersMatch(query.contactFilterSelf, query.contactFilterTarget,
                                pfxGetSelf(proxy), pfxGetTarget(proxy)) ||
        !boxMeetsProxy(box, proxy)) {
      return;
    }
    PfxContactCandidate candidates[PFX_MAX_CONTACT_CANDIDATES];
    const PfxUInt32 count =
        pfxContactCollidables(*query.collidable, query.transform, param.offsetCollidables[id],
                              param.offsetRigidStates[id].getTransform(), query.contactThreshold,
                              candidates, PFX_MAX_CONTACT_CANDIDATES);
    for (PfxUInt32 i = 0; i < count; ++i) {
      if (found.numContacts == maxContacts) {
        found.truncated = true;
        return;
      }
      out[found.numContacts].m_contact = candidates[i];
      out[found.numContacts].m_rigidBodyId = id;
      ++found.numContacts;
    }
  };

  // Depth first: median splits keep the depth within 32 levels, one waiting node each.
  const PfxRayBvhNode* nodes = param.bvhNodes;
  PfxUInt32 stack[64];
  int top = 0;
  if (boxMeetsCells(box, nodes[0].m_min, nodes[0].m_max)) stack[top++] = 0;
  while (top > 0) {
    const PfxRayBvhNode& node = nodes[stack[--top]];
    if (node.m_link & PFX_RAY_BVH_LEAF) {
      testBody(param.bvhProxies[node.m_link & ~PFX_RAY_BVH_LEAF]);
      continue;
    }
    const PfxUInt32 first = static_cast<PfxUInt32>(&node - nodes) + 1;
    const PfxUInt32 second = node.m_link;
    if (boxMeetsCells(box, nodes[second].m_min, nodes[second].m_max)) stack[top++] = second;
    if (boxMeetsCells(box, nodes[first].m_min, nodes[first].m_max)) stack[top++] = first;
  }
  result = found;
  return PFX_OK;
}

}  // namespace pfx
