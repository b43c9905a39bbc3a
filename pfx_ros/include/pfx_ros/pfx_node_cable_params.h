// ~cables and ~cloths: the node's cables and cloths (pfx_node_cables.h) read from its
// parameters, each a list of dicts. An entry that is refused (an unknown key, a value of the
// wrong type, a number out of range, an unknown link) is logged as an error naming the list,
// the entry's index and name and the field, and left out: the node starts with the rest.
#pragma once

#include <ros/ros.h>

#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

// Adds the declared cables and cloths to the simulation; returns how many were refused.
PfxUInt32 pfxAddDeclaredCablesAndCloths(const ros::NodeHandle& privateHandle,
                                        PfxNodeSimulation& simulation);

}  // namespace pfx
