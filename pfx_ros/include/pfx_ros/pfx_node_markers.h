// ~markers: a visualization_msgs/MarkerArray drawn through pfx's debug render (seed chapter
// 8), in the fixed frame. Namespace "shapes" holds one TRIANGLE_LIST per moving body,
// "static_shapes" the same for fixed bodies (ground, OctoMap, fixed robot bases), and
// "contacts", "aabbs", "joints" and "islands" the debug information, each as a LINE_LIST
// (id 0) and POINTS (id 1). Fixed bodies do not move, so they are sent only when a
// subscriber connects and after a load or reset; rviz keeps them meanwhile. Namespace
// "agents" draws each agent (pfx_node_agents.h) as five markers with consecutive ids, kept
// while it lives: a CYLINDER and two SPHEREs (its capsule), an ARROW along its heading and
// its name as TEXT_VIEW_FACING; when it is deleted they are sent once with action DELETE.
// Agents are not in "shapes", and the parked bodies of deleted ones are drawn nowhere.
// Namespace "cables" draws each cable as a LINE_STRIP through its particles, as wide as the
// cable, and "cloths" each cloth as a TRIANGLE_LIST of its surface; the id is the cable's or
// cloth's place in its list.
#pragma once

#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include <map>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_debug_render.h"
#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

class PfxNodeMarkers {
 public:
  PfxNodeMarkers(ros::NodeHandle& privateHandle, const std::string& fixedFrame);

  void publish(const PfxNodeSimulation& simulation, const ros::Time& stamp);

 private:
  // Lines and points that one render method drew.
  struct Drawing {
    std::vector<geometry_msgs::Point> linePoints;
    std::vector<std_msgs::ColorRGBA> lineColors;
    std::vector<geometry_msgs::Point> points;
    std::vector<std_msgs::ColorRGBA> pointColors;
  };
  void addLine(const PfxVector3& a, const PfxVector3& b, const PfxVector3& color);
  void addBoxEdges(const PfxTransform3& transform, const PfxVector3& halfExtent,
                   const PfxVector3& color);
  void addShapes(const PfxNodeSimulation& simulation, bool fixedBodies, const char* ns,
                 const ros::Time& stamp);
  void addAgents(const PfxNodeSimulation& simulation, const ros::Time& stamp);
  void addCablesAndCloths(const PfxNodeSimulation& simulation, const ros::Time& stamp);
  void addDrawing(const char* ns, const ros::Time& stamp);
  visualization_msgs::Marker makeMarker(const char* ns, PfxInt32 id, PfxInt32 type,
                                        const ros::Time& stamp) const;

  std::string m_fixedFrame;
  ros::Publisher m_publisher;
  bool m_sendStatic = true;
  PfxUInt32 m_sentGeneration = 0;
  PfxUInt32 m_sentModelChanges = 0;  // of the simulation's added models, when last sent
  PfxUInt32 m_drawnBodies = 0;        // bodies in the world when shapes were last drawn
  PfxDebugRender m_render;
  Drawing m_drawing;
  std::vector<visualization_msgs::Marker> m_bodyMarkers;  // by body id, while drawing shapes
  visualization_msgs::MarkerArray m_array;
  std::map<std::string, PfxInt32> m_agentIds;  // first marker id of each agent drawn last
  PfxInt32 m_nextAgentId = 0;
};

}  // namespace pfx
