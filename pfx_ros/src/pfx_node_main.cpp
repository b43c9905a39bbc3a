// pfx_node: a URDF robot simulated by pfx, see pfx_ros/pfx_node.h and the README.
#include <ros/ros.h>

#include <cstdio>

#include "pfx_ros/pfx_node.h"

int main(int argc, char** argv) {
  // Log lines appear as they happen also when stdout is a file or a pipe (roslaunch logs).
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  ros::init(argc, argv, "pfx_node");
  pfx::PfxNode node;
  if (!node.initialize()) return 1;
  node.run();
  return 0;
}
