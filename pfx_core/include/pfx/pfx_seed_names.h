// The seed's names for what pfx names otherwise, so that a program written from the seed
// (its chapters 2 to 8) compiles against pfx. pfx's own names stay the primary ones: the
// headers, the README and the errors use them; these only point at them and cost nothing.
// Everything the seed names that is not listed here is spelled the same in pfx
// (PfxRigidState, pfxFindPairs, PfxDecomposePairsParam, pfxCalcInertiaSphere,
// kPfxMotionTypeActive, ...).
//
// What the seed names and pfx does not have, and what stands in its place:
//   physics_effects.h            pfx/pfx.h
//   PfxPsp2TaskManager           PfxTbbTaskManager (a oneTBB arena; pfx_tbb_task_manager.h)
//   SCE_PFX_MESH_FLAG_HTGH_QUALITY (sic)  SCE_PFX_MESH_FLAG_HIGH_QUALITY below
//   PfxVector3 v(0.0f)           PfxVector3(0, 0, 0) or PfxVector3::Zero() (Eigen)
#pragma once

#include "pfx/base_level/base/pfx_common.h"
#include "pfx/base_level/base/pfx_vec_math.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/base_level/rigidbody/pfx_motion_type.h"
#include "pfx/high_level/pfx_debug_render.h"
#include "pfx/low_level/broadphase/pfx_update_broadphase_proxies.h"

namespace pfx {

// Types (seed chapters 2 and 3). The seed's vector library carries a float or a bool in a
// vector register; here they are plain scalars.
using ePfxMotionType = PfxMotionType;
using PfxFloatInVec = PfxFloat;
using PfxBoolInVec = PfxBool;

// The seed's vector library multiplies element by element thus (chapter 4, the broad phase's
// choice of axis).
inline PfxVector3 mulPerElem(const PfxVector3& a, const PfxVector3& b) { return a.cwiseProduct(b); }

// Error codes (seed chapters 4 and 5 name OUT_OF_WORLD and OUT_OF_MAX_PAIRS; the others
// follow the same pattern).
constexpr PfxInt32 SCE_PFX_OK = PFX_OK;
constexpr PfxInt32 SCE_PFX_ERR_INVALID_VALUE = PFX_ERR_INVALID_VALUE;
constexpr PfxInt32 SCE_PFX_ERR_INVALID_ALIGNMENT = PFX_ERR_INVALID_ALIGNMENT;
constexpr PfxInt32 SCE_PFX_ERR_OUT_OF_BUFFER = PFX_ERR_OUT_OF_BUFFER;
constexpr PfxInt32 SCE_PFX_ERR_OUT_OF_WORLD = PFX_ERR_OUT_OF_WORLD;
constexpr PfxInt32 SCE_PFX_ERR_OUT_OF_MAX_PAIRS = PFX_ERR_OUT_OF_MAX_PAIRS;
constexpr PfxInt32 SCE_PFX_ERR_INVALID_FLAG = PFX_ERR_INVALID_FLAG;
constexpr PfxInt32 SCE_PFX_ERR_NOT_CONVEX = PFX_ERR_NOT_CONVEX;
constexpr PfxInt32 SCE_PFX_ERR_OUT_OF_RANGE = PFX_ERR_OUT_OF_RANGE;
constexpr PfxInt32 SCE_PFX_ERR_DEGENERATE = PFX_ERR_DEGENERATE;
constexpr PfxInt32 SCE_PFX_ERR_NULL_POINTER = PFX_ERR_NULL_POINTER;

// What becomes of a body outside the world (seed chapter 5).
constexpr PfxUInt32 SCE_PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION = PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION;
constexpr PfxUInt32 SCE_PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY =
    PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY;

// Large mesh creation flags (seed chapter 2).
constexpr PfxUInt32 SCE_PFX_MESH_FLAG_USE_BVH = PFX_MESH_FLAG_USE_BVH;
constexpr PfxUInt32 SCE_PFX_MESH_FLAG_USE_QUANTIZED = PFX_MESH_FLAG_USE_QUANTIZED;
constexpr PfxUInt32 SCE_PFX_MESH_FLAG_HIGH_QUALITY = PFX_MESH_FLAG_HIGH_QUALITY;

// The four kinds of large mesh (seed chapter 2): how its islands are stored, crossed with
// whether its elements are quantized. In pfx the kind is the mesh's storage flags, which
// pfxGetLargeMeshType reads back.
constexpr PfxUInt32 PFX_LARGE_MESH_TYPE_EXPANDED_ARRAY = 0;
constexpr PfxUInt32 PFX_LARGE_MESH_TYPE_QUANTIZED_ARRAY = PFX_MESH_FLAG_USE_QUANTIZED;
constexpr PfxUInt32 PFX_LARGE_MESH_TYPE_EXPANDED_BVH = PFX_MESH_FLAG_USE_BVH;
constexpr PfxUInt32 PFX_LARGE_MESH_TYPE_QUANTIZED_BVH =
    PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED;
constexpr PfxUInt32 SCE_PFX_LARGE_MESH_TYPE_EXPANDED_ARRAY = PFX_LARGE_MESH_TYPE_EXPANDED_ARRAY;
constexpr PfxUInt32 SCE_PFX_LARGE_MESH_TYPE_QUANTIZED_ARRAY = PFX_LARGE_MESH_TYPE_QUANTIZED_ARRAY;
constexpr PfxUInt32 SCE_PFX_LARGE_MESH_TYPE_EXPANDED_BVH = PFX_LARGE_MESH_TYPE_EXPANDED_BVH;
constexpr PfxUInt32 SCE_PFX_LARGE_MESH_TYPE_QUANTIZED_BVH = PFX_LARGE_MESH_TYPE_QUANTIZED_BVH;

// One of PFX_LARGE_MESH_TYPE_*: the kind a mesh was built as.
inline PfxUInt32 pfxGetLargeMeshType(const PfxLargeTriMesh& mesh) {
  return mesh.m_flags & (PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED);
}

// Debug render flags (seed chapter 8).
constexpr PfxUInt32 SCE_PFX_DRENDER_MESH_FLG_ISLAND = PFX_DRENDER_MESH_FLG_ISLAND;
constexpr PfxUInt32 SCE_PFX_DRENDER_MESH_FLG_EDGE = PFX_DRENDER_MESH_FLG_EDGE;
constexpr PfxUInt32 SCE_PFX_DRENDER_MESH_FLG_FACET_AABB = PFX_DRENDER_MESH_FLG_FACET_AABB;
constexpr PfxUInt32 SCE_PFX_DRENDER_MESH_FLG_NORMAL = PFX_DRENDER_MESH_FLG_NORMAL;
constexpr PfxUInt32 SCE_PFX_DRENDER_MESH_FLG_THICKNESS = PFX_DRENDER_MESH_FLG_THICKNESS;
constexpr PfxUInt32 SCE_PFX_DRENDER_MESH_FLG_ALL = PFX_DRENDER_MESH_FLG_ALL;

}  // namespace pfx

// The seed's namespace (chapter 1): `using namespace sce::PhysicsEffects;` works too.
namespace sce {
namespace PhysicsEffects = ::pfx;
}  // namespace sce
