#include "pfx_ros/pfx_node_markers.h"

#include <algorithm>
#include <cmath>

#include "pfx_ros/pfx_ros_conversions.h"

namespace pfx {

namespace {

constexpr double kLineWidth = 0.005;  // m
constexpr double kPointSize = 0.03;   // m
// A resting robot's contact forces are hundreds of newtons: drawn at the debug render's
// default of 1 cm per newton they would reach metres above it.
constexpr PfxFloat kForceScale = PfxFloat(0.0005);  // m/N
// Arcs (joint limits) become chords of at most this angle.
constexpr PfxFloat kArcStep = PFX_PI / 16;
// An agent is drawn as a cylinder, two spheres, an arrow along its heading and its name.
constexpr PfxInt32 kMarkersPerAgent = 5;
const PfxVector3 kAgentColor(PfxFloat(1), PfxFloat(0.55), PfxFloat(0.1));
const PfxVector3 kCableColor(PfxFloat(0.15), PfxFloat(0.15), PfxFloat(0.15));
const PfxVector3 kClothColor(PfxFloat(0.2), PfxFloat(0.45), PfxFloat(0.85));

std_msgs::ColorRGBA toColor(const PfxVector3& rgb) {
  std_msgs::ColorRGBA c;
  c.r = std::clamp(float(rgb[0]), 0.0f, 1.0f);
  c.g = std::clamp(float(rgb[1]), 0.0f, 1.0f);
  c.b = std::clamp(float(rgb[2]), 0.0f, 1.0f);
  c.a = 1;
  return c;
}

}  // namespace

PfxNodeMarkers::PfxNodeMarkers(ros::NodeHandle& privateHandle, const std::string& fixedFrame)
    : m_fixedFrame(fixedFrame) {
  m_render.setForceScale(kForceScale);
  // A new subscriber has none of the fixed bodies yet.
  m_publisher = privateHandle.advertise<visualization_msgs::MarkerArray>(
      "markers", 1, ros::SubscriberStatusCallback([this](const ros::SingleSubscriberPublisher&) {
        m_sendStatic = true;
      }));

  m_render.setDebugRenderPointFunc([this](const PfxVector3& p, const PfxVector3& color) {
    m_drawing.points.push_back(pfxToPointMsg(p));
    m_drawing.pointColors.push_back(toColor(color));
  });
  m_render.setDebugRenderLineFunc([this](const PfxVector3& a, const PfxVector3& b,
                                         const PfxVector3& color) { addLine(a, b, color); });
  m_render.setDebugRenderArcFunc([this](const PfxVector3& center, const PfxVector3& axis,
                                        const PfxVector3& dir, PfxFloat radius, PfxFloat start,
                                        PfxFloat end, const PfxVector3& color) {
    const PfxVector3 side = axis.normalized().cross(dir);
    const int chords = std::max(1, int(std::ceil(std::abs(end - start) / kArcStep)));
    PfxVector3 previous = center + radius * (std::cos(start) * dir + std::sin(start) * side);
    for (int i = 1; i <= chords; ++i) {
      const PfxFloat angle = start + (end - start) * PfxFloat(i) / PfxFloat(chords);
      const PfxVector3 next = center + radius * (std::cos(angle) * dir + std::sin(angle) * side);
      addLine(previous, next, color);
      previous = next;
    }
  });
  m_render.setDebugRenderAabbFunc(
      [this](const PfxVector3& center, const PfxVector3& halfExtent, const PfxVector3& color) {
        PfxTransform3 transform = PfxTransform3::Identity();
        transform.translation() = center;
        addBoxEdges(transform, halfExtent, color);
      });
  m_render.setDebugRenderBoxFunc(
      [this](const PfxTransform3& transform, const PfxVector3& halfExtent,
             const PfxVector3& color) { addBoxEdges(transform, halfExtent, color); });
  m_render.setDebugRenderTriangleFunc([this](const PfxVector3& p0, const PfxVector3& p1,
                                             const PfxVector3& p2, const PfxVector3& color,
                                             PfxUInt32 bodyId) {
    if (bodyId >= m_bodyMarkers.size()) return;
    visualization_msgs::Marker& marker = m_bodyMarkers[bodyId];
    if (marker.points.empty()) marker.color = toColor(color);
    marker.points.push_back(pfxToPointMsg(p0));
    marker.points.push_back(pfxToPointMsg(p1));
    marker.points.push_back(pfxToPointMsg(p2));
  });
}

void PfxNodeMarkers::addLine(const PfxVector3& a, const PfxVector3& b, const PfxVector3& color) {
  m_drawing.linePoints.push_back(pfxToPointMsg(a));
  m_drawing.linePoints.push_back(pfxToPointMsg(b));
  m_drawing.lineColors.push_back(toColor(color));
  m_drawing.lineColors.push_back(toColor(color));
}

void PfxNodeMarkers::addBoxEdges(const PfxTransform3& transform, const PfxVector3& halfExtent,
                                 const PfxVector3& color) {
  PfxVector3 corners[8];
  for (int i = 0; i < 8; ++i) {
    const PfxVector3 local((i & 1) ? halfExtent[0] : -halfExtent[0],
                           (i & 2) ? halfExtent[1] : -halfExtent[1],
                           (i & 4) ? halfExtent[2] : -halfExtent[2]);
    corners[i] = transform * local;
  }
  // Corners that differ in exactly one bit share an edge.
  for (int i = 0; i < 8; ++i) {
    for (int bit = 1; bit < 8; bit <<= 1) {
      if ((i & bit) == 0) addLine(corners[i], corners[i | bit], color);
    }
  }
}

visualization_msgs::Marker PfxNodeMarkers::makeMarker(const char* ns, PfxInt32 id, PfxInt32 type,
                                                      const ros::Time& stamp) const {
  visualization_msgs::Marker marker;
  marker.header.frame_id = m_fixedFrame;
  marker.header.stamp = stamp;
  marker.ns = ns;
  marker.id = id;
  marker.type = type;
  marker.action = visualization_msgs::Marker::ADD;
  marker.pose.orientation.w = 1;
  marker.scale.x = marker.scale.y = marker.scale.z = 1;
  marker.color.a = 1;
  return marker;
}

void PfxNodeMarkers::addShapes(const PfxNodeSimulation& simulation, bool fixedBodies,
                               const char* ns, const ros::Time& stamp) {
  const PfxWorld& world = simulation.getWorld();
  const PfxNodeAgentSet& agents = simulation.getAgents();
  const PfxUInt32 numBodies = world.getNumRigidBodies();
  m_render.resetVisible(numBodies);
  m_bodyMarkers.assign(numBodies, visualization_msgs::Marker());
  // Agents have a namespace of their own (addAgents).
  for (PfxUInt32 id = 0; id < numBodies; ++id) {
    const bool fixed = world.getRigidState(id).getMotionType() == kPfxMotionTypeFixed;
    // A removed body (a deleted model's) draws nothing: its markers are deleted in both
    // namespaces.
    m_render.setVisible(id, !world.hasRigidBody(id) ||
                                (fixed == fixedBodies && !agents.isAgentBody(id)));
  }
  m_drawing = Drawing();
  m_render.renderShapes(world);
  for (PfxUInt32 id = 0; id < numBodies; ++id) {
    if (!m_render.isVisible(id)) continue;
    visualization_msgs::Marker& drawn = m_bodyMarkers[id];
    visualization_msgs::Marker marker =
        makeMarker(ns, PfxInt32(id), visualization_msgs::Marker::TRIANGLE_LIST, stamp);
    if (drawn.points.empty()) {
      marker.action = visualization_msgs::Marker::DELETE;
    } else {
      marker.color = drawn.color;
      marker.points.swap(drawn.points);
    }
    m_array.markers.push_back(std::move(marker));
  }
  // Bodies truncated away (the newest model deleted) are gone from the ids.
  for (PfxUInt32 id = numBodies; id < m_drawnBodies; ++id) {
    visualization_msgs::Marker gone =
        makeMarker(ns, PfxInt32(id), visualization_msgs::Marker::TRIANGLE_LIST, stamp);
    gone.action = visualization_msgs::Marker::DELETE;
    m_array.markers.push_back(std::move(gone));
  }
  m_render.resetVisible(numBodies);
}

void PfxNodeMarkers::addDrawing(const char* ns, const ros::Time& stamp) {
  visualization_msgs::Marker lines =
      makeMarker(ns, 0, visualization_msgs::Marker::LINE_LIST, stamp);
  lines.scale.x = kLineWidth;
  if (m_drawing.linePoints.empty()) {
    lines.action = visualization_msgs::Marker::DELETE;
  } else {
    lines.points.swap(m_drawing.linePoints);
    lines.colors.swap(m_drawing.lineColors);
  }
  m_array.markers.push_back(std::move(lines));

  visualization_msgs::Marker points = makeMarker(ns, 1, visualization_msgs::Marker::POINTS, stamp);
  points.scale.x = points.scale.y = kPointSize;
  if (m_drawing.points.empty()) {
    points.action = visualization_msgs::Marker::DELETE;
  } else {
    points.points.swap(m_drawing.points);
    points.colors.swap(m_drawing.pointColors);
  }
  m_array.markers.push_back(std::move(points));
  m_drawing = Drawing();
}

void PfxNodeMarkers::addAgents(const PfxNodeSimulation& simulation, const ros::Time& stamp) {
  const PfxNodeAgentSet& agents = simulation.getAgents();
  std::map<std::string, PfxInt32> drawn;
  for (PfxUInt32 i = 0; i < agents.getNumAgents(); ++i) {
    const PfxNodeAgentSpec& spec = agents.getAgentSpec(i);
    const PfxNodeAgentState state = agents.getAgentState(i);
    // An agent keeps its ids while it lives, so that rviz replaces its markers in place.
    const auto known = m_agentIds.find(spec.name);
    const PfxInt32 first = known != m_agentIds.end() ? known->second : m_nextAgentId;
    if (known == m_agentIds.end()) m_nextAgentId += kMarkersPerAgent;
    drawn[spec.name] = first;

    const double radius = spec.radius;
    const double height = spec.height;
    const PfxQuat heading(Eigen::AngleAxis<PfxFloat>(state.yaw, PfxVector3::UnitZ()));
    auto place = [&](visualization_msgs::Marker& marker, double z) {
      marker.pose.position = pfxToPointMsg(state.foot + PfxVector3(0, 0, PfxFloat(z)));
      marker.pose.orientation = pfxToQuaternionMsg(heading);
      marker.color = toColor(kAgentColor);
    };
    visualization_msgs::Marker body =
        makeMarker("agents", first, visualization_msgs::Marker::CYLINDER, stamp);
    place(body, height / 2);
    body.scale.x = body.scale.y = 2 * radius;
    body.scale.z = height - 2 * radius;
    m_array.markers.push_back(body);
    for (int end = 0; end < 2; ++end) {
      visualization_msgs::Marker cap =
          makeMarker("agents", first + 1 + end, visualization_msgs::Marker::SPHERE, stamp);
      place(cap, end == 0 ? radius : height - radius);
      cap.scale.x = cap.scale.y = cap.scale.z = 2 * radius;
      m_array.markers.push_back(cap);
    }
    // Which way it faces: an arrow from the middle of the body, one radius out of it.
    visualization_msgs::Marker nose =
        makeMarker("agents", first + 3, visualization_msgs::Marker::ARROW, stamp);
    place(nose, height / 2);
    nose.scale.x = 2 * radius;
    nose.scale.y = nose.scale.z = radius / 3;
    m_array.markers.push_back(nose);
    visualization_msgs::Marker label =
        makeMarker("agents", first + 4, visualization_msgs::Marker::TEXT_VIEW_FACING, stamp);
    place(label, height + 0.15);
    label.scale.z = 0.15;
    label.text = spec.name;
    m_array.markers.push_back(label);
  }
  for (const auto& [name, first] : m_agentIds) {
    if (drawn.count(name) != 0) continue;
    for (PfxInt32 k = 0; k < kMarkersPerAgent; ++k) {
      visualization_msgs::Marker gone =
          makeMarker("agents", first + k, visualization_msgs::Marker::CYLINDER, stamp);
      gone.action = visualization_msgs::Marker::DELETE;
      m_array.markers.push_back(gone);
    }
  }
  m_agentIds.swap(drawn);
}

void PfxNodeMarkers::addCablesAndCloths(const PfxNodeSimulation& simulation,
                                        const ros::Time& stamp) {
  const std::vector<PfxNodeCableSpec>& cables = simulation.getCables();
  for (PfxUInt32 i = 0; i < cables.size(); ++i) {
    visualization_msgs::Marker strip =
        makeMarker("cables", PfxInt32(i), visualization_msgs::Marker::LINE_STRIP, stamp);
    strip.scale.x = 2 * cables[i].radius;
    strip.color = toColor(kCableColor);
    for (const PfxParticle& p : simulation.getCableGroup(i).particles) {
      strip.points.push_back(pfxToPointMsg(p.m_position));
    }
    m_array.markers.push_back(std::move(strip));
  }
  for (PfxUInt32 i = 0; i < simulation.getCloths().size(); ++i) {
    visualization_msgs::Marker surface =
        makeMarker("cloths", PfxInt32(i), visualization_msgs::Marker::TRIANGLE_LIST, stamp);
    surface.color = toColor(kClothColor);
    const PfxParticleGroup& group = simulation.getClothGroup(i);
    for (const PfxUInt32 corner : group.triangleIndices) {
      surface.points.push_back(pfxToPointMsg(group.particles[corner].m_position));
    }
    m_array.markers.push_back(std::move(surface));
  }
}

void PfxNodeMarkers::publish(const PfxNodeSimulation& simulation, const ros::Time& stamp) {
  if (m_publisher.getNumSubscribers() == 0) return;
  const PfxWorld& world = simulation.getWorld();
  m_array.markers.clear();

  const bool sendStatic = m_sendStatic || m_sentGeneration != simulation.getGeneration() ||
                          m_sentModelChanges != simulation.getModelChanges();
  addShapes(simulation, false, "shapes", stamp);
  addAgents(simulation, stamp);
  addCablesAndCloths(simulation, stamp);
  if (sendStatic) {
    addShapes(simulation, true, "static_shapes", stamp);
    m_sendStatic = false;
    m_sentGeneration = simulation.getGeneration();
    m_sentModelChanges = simulation.getModelChanges();
  }
  m_drawnBodies = world.getNumRigidBodies();

  m_drawing = Drawing();
  m_render.renderContact(world);
  addDrawing("contacts", stamp);
  m_render.renderAabb(world);
  addDrawing("aabbs", stamp);
  m_render.renderJoint(world);
  addDrawing("joints", stamp);
  m_render.renderIsland(world);
  addDrawing("islands", stamp);

  m_publisher.publish(m_array);
}

}  // namespace pfx
