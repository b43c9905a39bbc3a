// The cables and cloths of pfx_node: particle groups of the core (pfx_particle_group.h)
// declared in physical units and tied to links or to the world. No ROS types here:
// PfxNodeSimulation adds them to its world, pfx_node_cable_params.h reads them from the
// node's parameters.
//
// Stiffness. The core's constraints take compliance (XPBD, m/N). A cable's stiffness is its
// axial stiffness EA (N: the tension that would stretch it by its own length), so a segment
// of rest length l gets compliance l / EA. A cloth's is a membrane stiffness (N/m: the
// tension per metre of width that would stretch it by its own length), and each stretch
// constraint gets compliance 1 / stiffness, exact for the rows and columns of a grid of square
// cells. 0 (the default) makes either inextensible.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_particle_group.h"

namespace pfx {

// Bounds of what the node accepts: beyond them a cable or cloth is refused.
constexpr PfxUInt32 kPfxNodeMaxCableSegments = 1000;
constexpr PfxUInt32 kPfxNodeMaxClothResolution = 200;  // particles along an edge
constexpr PfxFloat kPfxNodeMaxCableLength = 100;       // m, also a cloth's edge
constexpr PfxFloat kPfxNodeMaxParticleRadius = 1;      // m
constexpr PfxFloat kPfxNodeMaxMassPerMetre = 1000;     // kg/m, also kg/m^2 of cloth

// The world, as the link of a cable end or of a cloth's pins.
extern const char* const kPfxNodeWorldLink;

struct PfxNodeCableSpec {
  std::string name;
  std::string startLink = kPfxNodeWorldLink;  // a link or body name, or "world"
  PfxVector3 startPoint = PfxVector3::Zero();  // in the link's frame (the world's for "world")
  // Empty: the end hangs free, and the cable starts straight down from its start.
  std::string endLink;
  PfxVector3 endPoint = PfxVector3::Zero();
  PfxFloat length = 1;                 // m; at least the distance between the two ends
  PfxFloat radius = PfxFloat(0.01);    // m: for contacts and rays
  PfxFloat massPerMetre = PfxFloat(0.1);  // kg/m
  PfxFloat stiffness = 0;              // EA (N); 0: inextensible
  PfxUInt32 segments = 20;             // particles: segments + 1
  PfxUInt32 iterations = 20;           // solver iterations per sub-step
};

struct PfxNodeClothSpec {
  std::string name;
  // The rectangle, in the world: particle (i, j) starts at corner + i / (resolutionU - 1)
  // edgeU + j / (resolutionV - 1) edgeV.
  PfxVector3 corner = PfxVector3::Zero();
  PfxVector3 edgeU = PfxVector3(1, 0, 0);
  PfxVector3 edgeV = PfxVector3(0, 1, 0);
  PfxUInt32 resolutionU = 11;
  PfxUInt32 resolutionV = 11;
  PfxFloat massPerArea = PfxFloat(0.2);  // kg/m^2
  PfxFloat radius = PfxFloat(0.01);      // m
  PfxFloat stiffness = 0;                // N/m; 0: inextensible
  PfxUInt32 iterations = 2;              // solver iterations per sub-step
  // Corners and edges held where they start, to pinLink: "corner" (i = j = 0), "corner_u"
  // (the corner at corner + edgeU), "corner_v", "corner_uv", "edge_u" (j = 0, along edgeU),
  // "edge_v" (i = 0), "edge_u_far" (j = resolutionV - 1), "edge_v_far" (i = resolutionU - 1).
  std::vector<std::string> pinned;
  std::string pinLink = kPfxNodeWorldLink;
};

// Empty when the numbers of the spec are valid, else "<field>: <why>". Names and links are
// for the simulation to check.
std::string pfxCheckCableSpec(const PfxNodeCableSpec& spec);
std::string pfxCheckClothSpec(const PfxNodeClothSpec& spec);

// The first non-empty reason, in the order given (a spec's fields are checked and reported in
// the order a user reads them), or "" when all are empty.
std::string pfxFirstReason(std::initializer_list<std::string> reasons);

// Where a cable end or a cloth's pins are held: a body (PFX_PARTICLE_PIN_WORLD for the
// world) and its pose now, to turn world points into the body's frame.
struct PfxNodeAnchorBody {
  PfxUInt32 bodyId = PFX_PARTICLE_PIN_WORLD;
  PfxTransform3 pose = PfxTransform3::Identity();
};

// Writes a checked cable into `group`: from `start` to `end` (world points) when `endBody`
// is given, else hanging free from `start`; its particles start on a V of the cable's
// length below the straight line. Rejects (PFX_ERR_INVALID_VALUE, *message saying why) a
// length shorter than the distance between the ends.
PfxInt32 pfxBuildNodeCable(const PfxNodeCableSpec& spec, const PfxVector3& start,
                           const PfxNodeAnchorBody& startBody, const PfxVector3& end,
                           const PfxNodeAnchorBody* endBody, PfxParticleGroupBuilder& group,
                           std::string* message);
// Moves the particles of a cable from pfxBuildNodeCable to where it comes to rest hanging
// from its pins, in `gravity`, alone (what it would touch is not looked at): a cable then
// starts at rest in its hanging shape instead of swinging down from the V. Fails as
// PfxWorld::step fails, leaving `group` as it was.
PfxInt32 pfxSettleNodeCable(const PfxVector3& gravity, PfxParticleGroupBuilder& group);
// Writes a checked cloth into `group`, its pins held by `pinBody`.
void pfxBuildNodeCloth(const PfxNodeClothSpec& spec, const PfxNodeAnchorBody& pinBody,
                       PfxParticleGroupBuilder& group);

}  // namespace pfx
