// Overlap depth between two posed shapes, computed the same way for every engine from the
// poses it reports, so that `penetration_max` does not depend on what an engine says
// about its own contacts.
#pragma once

#include <optional>
#include <vector>

#include "bench_engine.h"
#include "bench_scene.h"

namespace pfxbench {

// How far the two shapes interpenetrate (0 when apart): the shortest translation that
// separates them. Boxes and spheres only; nothing for capsules and cylinders.
std::optional<double> overlapDepth(const ShapeDesc& a, const BodyState& poseA,
                                   const ShapeDesc& b, const BodyState& poseB);

// Deepest overlap between any two bodies of which at least one is dynamic and that no joint
// holds together, over the shapes overlapDepth handles. NaN if a pose is not finite.
double deepestOverlap(const Scene& scene, const std::vector<BodyState>& states);

}  // namespace pfxbench
