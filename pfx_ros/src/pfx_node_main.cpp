// pfx_node: a URDF robot simulated by pfx, see pfx_ros/pfx_node.h and the README.
#include <ros/ros.h>

#include "pfx_ros/pfx_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "pfx_node");
  pfx::PfxNode node;
  if (!node.initialize()) return 1;
  node.run();
  return 0;
}
