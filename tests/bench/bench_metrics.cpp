#include "bench_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bench_overlap.h"

namespace pfxbench {

namespace {

// Like std::max, but a NaN on either side wins, so that a blown-up run shows as NaN.
double maxKeepingNaN(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return kNaN;
  return std::max(a, b);
}

struct Conserved {
  Vec3 angularMomentum = Vec3::Zero();  // about the world origin
  double energy = 0;                    // kinetic plus gravitational potential
};

Conserved conserved(const Scene& scene, const std::vector<BodyState>& states) {
  Conserved total;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDesc& body = scene.bodies[i];
    if (body.fixed) continue;
    const BodyState& s = states[i];
    const Eigen::Matrix3d r = s.orientation.normalized().toRotationMatrix();
    const Eigen::Matrix3d inertia = r * body.inertia.asDiagonal() * r.transpose();
    const Vec3 spin = inertia * s.angularVelocity;
    total.angularMomentum += body.mass * s.position.cross(s.linearVelocity) + spin;
    total.energy += 0.5 * body.mass * s.linearVelocity.squaredNorm() +
                    0.5 * s.angularVelocity.dot(spin) - body.mass * scene.gravity.dot(s.position);
  }
  return total;
}

double relativeChange(double start, double end) { return std::abs(end - start) / std::abs(start); }

Vec3 trackedHalfExtents(const ShapeDesc& shape) {
  switch (shape.type) {
    case ShapeType::Box: return shape.halfExtents;
    case ShapeType::Sphere: return Vec3::Constant(shape.radius);
    case ShapeType::Capsule: return Vec3(shape.halfLength + shape.radius, shape.radius, shape.radius);
    case ShapeType::Cylinder: return Vec3(shape.halfLength, shape.radius, shape.radius);
  }
  return Vec3::Zero();
}

}  // namespace

MetricRecorder::MetricRecorder(const Scene& scene) : m_scene(scene) {}

void MetricRecorder::observe(const std::vector<BodyState>& states) {
  if (m_first.empty()) m_first = states;
  m_last = states;
  if (m_scene.hasMetric(Metric::StackDrift)) {
    for (std::size_t i = 0; i < states.size(); ++i) {
      if (m_scene.bodies[i].fixed) continue;
      const Vec3 moved = states[i].position - m_scene.bodies[i].position;
      m_stackDrift = maxKeepingNaN(m_stackDrift, moved.allFinite() ? moved.norm() : kNaN);
    }
  }
  if (m_scene.hasMetric(Metric::PenetrationMax)) {
    m_penetration = maxKeepingNaN(m_penetration, deepestOverlap(m_scene, states));
  }
}

void MetricRecorder::observeJoints(const std::vector<JointAnchors>& anchors) {
  for (const JointAnchors& joint : anchors) {
    const Vec3 gap = joint.onB - joint.onA;
    m_jointGap = maxKeepingNaN(m_jointGap, gap.allFinite() ? gap.norm() : kNaN);
  }
}

double MetricRecorder::value(Metric metric) const {
  if (m_last.empty()) return kNaN;
  switch (metric) {
    case Metric::StackDrift: return m_stackDrift;
    case Metric::PenetrationMax: return m_penetration;
    case Metric::EnergyDrift:
      return relativeChange(conserved(m_scene, m_first).energy, conserved(m_scene, m_last).energy);
    case Metric::MomentumDrift:
      return relativeChange(conserved(m_scene, m_first).angularMomentum.norm(),
                            conserved(m_scene, m_last).angularMomentum.norm());
    case Metric::Escaped: {
      int escaped = 0;
      for (std::size_t i = 0; i < m_last.size(); ++i) {
        // A NaN position fails the containment test and counts as escaped.
        if (!m_scene.bodies[i].fixed && !m_scene.keepInside.contains(m_last[i].position)) {
          ++escaped;
        }
      }
      return escaped;
    }
    case Metric::JointGapMax: return m_jointGap;
    case Metric::PositionError:
    case Metric::BytesPerBody:
    case Metric::MsPerStep:
    case Metric::MsPerStepPerRobot:
    case Metric::CpuMsPerStepPerRobot: break;
  }
  return kNaN;
}

void appendTrackedPoints(const Scene& scene, const std::vector<BodyState>& states,
                         std::vector<Vec3>& points) {
  auto appendCorners = [&](std::size_t i) {
    const Vec3 half = trackedHalfExtents(scene.bodies[i].shape);
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 local((corner & 1) ? half.x() : -half.x(), (corner & 2) ? half.y() : -half.y(),
                       (corner & 4) ? half.z() : -half.z());
      points.push_back(states[i].position + states[i].orientation.normalized() * local);
    }
  };
  if (!scene.trackedBodies.empty()) {
    for (int i : scene.trackedBodies) appendCorners(static_cast<std::size_t>(i));
    return;
  }
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    if (!scene.bodies[i].fixed) appendCorners(i);
  }
}

double largestDeviation(const std::vector<Vec3>& run, const std::vector<Vec3>& reference) {
  if (run.size() != reference.size() || run.empty()) return kNaN;
  double largest = 0;
  for (std::size_t i = 0; i < run.size(); ++i) {
    const Vec3 d = run[i] - reference[i];
    largest = maxKeepingNaN(largest, d.allFinite() ? d.norm() : kNaN);
  }
  return largest;
}

}  // namespace pfxbench
