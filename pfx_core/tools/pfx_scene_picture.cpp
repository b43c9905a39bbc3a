#include "pfx_scene_picture.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>

#include "pfx/high_level/pfx_debug_render.h"

namespace pfx {

namespace {

constexpr PfxFloat kAmbient = PfxFloat(0.35);
constexpr PfxFloat kDiffuse = PfxFloat(0.65);
// A triangle is split while its longest edge exceeds this fraction of its distance from the
// eye: near the camera pieces get small, toward the horizon they stay large, so that a
// ground plane reaching far away is sorted correctly against the bodies on it.
constexpr PfxFloat kSplitRatio = PfxFloat(0.15);
constexpr int kMaxSplitLevels = 9;

// Bounds of the bodies that move, or of every body when none moves. `moving` says which.
bool sceneBounds(const PfxWorld& world, PfxVector3& lower, PfxVector3& upper, bool* moving) {
  bool found = false;
  for (const bool movingOnly : {true, false}) {
    for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
      const PfxRigidState& state = world.getRigidState(id);
      if (movingOnly && state.getMotionType() == kPfxMotionTypeFixed) continue;
      PfxVector3 center, half;
      world.getCollidable(id).getWorldAabb(state.getTransform(), center, half);
      if (!pfxIsFinite(center) || !pfxIsFinite(half)) continue;
      lower = found ? lower.cwiseMin(center - half) : PfxVector3(center - half);
      upper = found ? upper.cwiseMax(center + half) : PfxVector3(center + half);
      found = true;
    }
    if (found) {
      if (moving) *moving = movingOnly;
      return true;
    }
  }
  return false;
}

// Lowest and highest of the box's corners along `up`.
void extentAlong(const PfxVector3& lower, const PfxVector3& upper, const PfxVector3& up,
                 PfxFloat& low, PfxFloat& high) {
  low = std::numeric_limits<PfxFloat>::max();
  high = -low;
  for (int corner = 0; corner < 8; ++corner) {
    const PfxVector3 p((corner & 1) ? upper.x() : lower.x(), (corner & 2) ? upper.y() : lower.y(),
                       (corner & 4) ? upper.z() : lower.z());
    low = std::min(low, p.dot(up));
    high = std::max(high, p.dot(up));
  }
}

// Height along `up` of what the moving bodies stand on: the highest top of a fixed body
// that is not above their lowest point (a ground plane), else that lowest point.
PfxFloat groundHeight(const PfxWorld& world, const PfxVector3& up, PfxFloat tolerance) {
  PfxVector3 lower = PfxVector3::Zero(), upper = PfxVector3::Zero();
  bool moving = false;
  if (!sceneBounds(world, lower, upper, &moving)) return 0;
  PfxFloat lowest, highest;
  extentAlong(lower, upper, up, lowest, highest);
  if (!moving) return lowest;
  PfxFloat ground = -std::numeric_limits<PfxFloat>::max();
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    const PfxRigidState& state = world.getRigidState(id);
    if (state.getMotionType() != kPfxMotionTypeFixed) continue;
    PfxVector3 center, half;
    world.getCollidable(id).getWorldAabb(state.getTransform(), center, half);
    PfxFloat bottom, top;
    extentAlong(center - half, center + half, up, bottom, top);
    if (top <= lowest + tolerance) ground = std::max(ground, top);
  }
  return ground > -std::numeric_limits<PfxFloat>::max() ? ground : lowest;
}

// Two unit vectors perpendicular to `up` and to each other, the first as close to world X
// as `up` allows.
void horizontalBasis(const PfxVector3& up, PfxVector3& first, PfxVector3& second) {
  PfxVector3 x = PfxVector3::UnitX() - up * up.x();
  if (x.norm() < PfxFloat(0.1)) x = PfxVector3::UnitY() - up * up.y();
  first = x.normalized();
  second = up.cross(first);
}

// 1, 2 or 5 times a power of ten, near `value`.
PfxFloat niceStep(PfxFloat value) {
  const PfxFloat power = std::pow(PfxFloat(10), std::floor(std::log10(value)));
  const PfxFloat m = value / power;
  return power * (m < 1.5f ? 1 : m < 3.5f ? 2 : m < 7.5f ? 5 : 10);
}

}  // namespace

PfxScenePicture::PfxScenePicture(PfxUInt32 width, PfxUInt32 height)
    : m_width(std::clamp<PfxUInt32>(width, 16, 8192)),
      m_height(std::clamp<PfxUInt32>(height, 16, 8192)) {}

PfxSceneCamera PfxScenePicture::frameScene(const PfxWorld& world, const PfxVector3& up,
                                           PfxFloat fieldOfView) {
  PfxSceneCamera camera;
  camera.up = up.norm() > PFX_EPSILON ? PfxVector3(up.normalized()) : PfxVector3::UnitZ();
  camera.fieldOfView = fieldOfView;
  PfxVector3 lower = PfxVector3::Constant(-1), upper = PfxVector3::Constant(1);
  sceneBounds(world, lower, upper, nullptr);
  const PfxFloat radius = std::max((upper - lower).norm() / 2, PfxFloat(0.1));
  camera.target = (lower + upper) / 2;
  PfxVector3 first, second;
  horizontalBasis(camera.up, first, second);
  const PfxVector3 direction = (PfxFloat(0.62) * first - PfxFloat(0.7) * second +
                                PfxFloat(0.42) * camera.up).normalized();
  const PfxFloat halfAngle = fieldOfView * PFX_PI / 360;
  camera.position = camera.target + direction * (radius / std::sin(halfAngle) * PfxFloat(1.05));
  return camera;
}

PfxInt32 PfxScenePicture::setCamera(const PfxSceneCamera& camera) {
  const PfxVector3 view = camera.target - camera.position;
  if (!pfxIsFinite(camera.position) || !pfxIsFinite(camera.target) || !pfxIsFinite(camera.up) ||
      !(camera.fieldOfView > 1 && camera.fieldOfView < 170) || view.norm() < PFX_EPSILON ||
      camera.up.norm() < PFX_EPSILON ||
      view.normalized().cross(camera.up.normalized()).norm() < PfxFloat(1e-3)) {
    return PFX_ERR_INVALID_VALUE;
  }
  m_camera = camera;
  m_hasCamera = true;
  return PFX_OK;
}

PfxInt32 PfxScenePicture::setLightDirection(const PfxVector3& direction) {
  if (!pfxIsFinite(direction) || direction.norm() < PFX_EPSILON) return PFX_ERR_INVALID_VALUE;
  m_light = direction.normalized();
  return PFX_OK;
}

void PfxScenePicture::addTriangle(const PfxVector3& a, const PfxVector3& b, const PfxVector3& c,
                                  const PfxVector3& color, Layer layer, int level) {
  const PfxVector3 corners[3] = {a, b, c};
  PfxVector3 view[3];
  bool allBehind = true, anyBehind = false;
  for (int k = 0; k < 3; ++k) {
    view[k] = m_view * (corners[k] - m_eye);
    const bool behind = -view[k].z() < m_nearDepth;
    allBehind = allBehind && behind;
    anyBehind = anyBehind || behind;
  }
  if (allBehind) return;
  if (!anyBehind) {
    // Entirely beyond one edge of the picture: nothing of it shows.
    const PfxFloat tanX = PfxFloat(m_width) / 2 / m_focal, tanY = PfxFloat(m_height) / 2 / m_focal;
    int left = 0, right = 0, below = 0, above = 0;
    for (const PfxVector3& v : view) {
      const PfxFloat depth = -v.z();
      left += v.x() < -tanX * depth;
      right += v.x() > tanX * depth;
      below += v.y() < -tanY * depth;
      above += v.y() > tanY * depth;
    }
    if (left == 3 || right == 3 || below == 3 || above == 3) return;
  }
  const PfxFloat nearest = std::min({-view[0].z(), -view[1].z(), -view[2].z()});
  const PfxFloat longest =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  if (level < kMaxSplitLevels &&
      (anyBehind || longest > std::pow(kSplitRatio * std::max(nearest, m_nearDepth), 2))) {
    const PfxVector3 ab = (a + b) / 2, bc = (b + c) / 2, ca = (c + a) / 2;
    addTriangle(a, ab, ca, color, layer, level + 1);
    addTriangle(ab, b, bc, color, layer, level + 1);
    addTriangle(ca, bc, c, color, layer, level + 1);
    addTriangle(ab, bc, ca, color, layer, level + 1);
    return;
  }
  if (anyBehind) return;
  Primitive p;
  p.line = false;
  p.layer = layer;
  p.depth = -(view[0].z() + view[1].z() + view[2].z()) / 3;
  for (int k = 0; k < 3; ++k) {
    p.x[k] = PfxFloat(m_width) / 2 + m_focal * view[k].x() / -view[k].z();
    p.y[k] = PfxFloat(m_height) / 2 - m_focal * view[k].y() / -view[k].z();
  }
  const PfxVector3 normal = (b - a).cross(c - a).normalized();
  p.color = color * (kAmbient + kDiffuse * std::max(PfxFloat(0), -normal.dot(m_light)));
  m_primitives.push_back(p);
}

// A grid on the ground's plane around the scene, in cells of 1, 2 or 5 times a power of ten
// metres, drawn over the ground and under everything else.
void PfxScenePicture::addGrid(const PfxWorld& world) {
  PfxVector3 lower = PfxVector3::Constant(-1), upper = PfxVector3::Constant(1);
  sceneBounds(world, lower, upper, nullptr);
  const PfxVector3 center = (lower + upper) / 2;
  const PfxVector3 origin = center + (m_groundHeight - center.dot(m_up)) * m_up;
  const PfxFloat reach = std::max(PfxFloat(1), PfxFloat(1.5) * (upper - lower).norm());
  const PfxFloat step = niceStep(reach / 6);
  const int cells = static_cast<int>(std::ceil(reach / step));
  PfxVector3 first, second;
  horizontalBasis(m_up, first, second);
  // Lines on multiples of the step, so that the grid stays put while the scene moves.
  const PfxVector3 snapped = origin - first * std::fmod(origin.dot(first), step) -
                             second * std::fmod(origin.dot(second), step);
  for (int axis = 0; axis < 2; ++axis) {
    const PfxVector3 along = axis == 0 ? first : second;
    const PfxVector3 across = axis == 0 ? second : first;
    for (int i = -cells; i <= cells; ++i) {
      const PfxVector3 a = snapped + across * (PfxFloat(i) * step) - along * (PfxFloat(cells) * step);
      const PfxVector3 b = a + along * (PfxFloat(2 * cells) * step);
      // Clipped to the part in front of the eye.
      PfxVector3 va = m_view * (a - m_eye), vb = m_view * (b - m_eye);
      const PfxFloat da = -va.z() - m_nearDepth, db = -vb.z() - m_nearDepth;
      if (da < 0 && db < 0) continue;
      if (da < 0) va += (vb - va) * (da / (da - db));
      if (db < 0) vb += (va - vb) * (db / (db - da));
      Primitive p;
      p.line = true;
      p.layer = kLayerGrid;
      p.depth = 0;
      p.x[0] = PfxFloat(m_width) / 2 + m_focal * va.x() / -va.z();
      p.y[0] = PfxFloat(m_height) / 2 - m_focal * va.y() / -va.z();
      p.x[1] = PfxFloat(m_width) / 2 + m_focal * vb.x() / -vb.z();
      p.y[1] = PfxFloat(m_height) / 2 - m_focal * vb.y() / -vb.z();
      p.x[2] = p.y[2] = 0;
      p.color = PfxVector3::Constant(PfxFloat(0.3));
      m_primitives.push_back(p);
    }
  }
}

void PfxScenePicture::collect(const PfxWorld& world, const PfxSceneCamera& camera) {
  m_usedCamera = camera;
  m_eye = camera.position;
  const PfxVector3 back = (camera.position - camera.target).normalized();
  const PfxVector3 right = camera.up.cross(back).normalized();
  m_view.row(0) = right;
  m_view.row(1) = back.cross(right);
  m_view.row(2) = back;
  m_focal = PfxFloat(m_height) / 2 / std::tan(camera.fieldOfView * PFX_PI / 360);
  m_nearDepth = std::max(PfxFloat(1e-3), PfxFloat(1e-3) * (camera.position - camera.target).norm());
  m_up = camera.up.normalized();
  PfxVector3 lower = PfxVector3::Zero(), upper = PfxVector3::Zero();
  sceneBounds(world, lower, upper, nullptr);
  m_groundTolerance = std::max(PfxFloat(0.005), PfxFloat(0.01) * (upper - lower).norm());
  m_groundHeight = groundHeight(world, m_up, m_groundTolerance);
  m_primitives.clear();
  m_overlayLines.clear();
  m_overlayPoints.clear();

  PfxDebugRender render;
  render.setDebugRenderTriangleFunc([this](const PfxVector3& a, const PfxVector3& b,
                                           const PfxVector3& c, const PfxVector3& color, PfxUInt32) {
    // Faces turned away from the eye are hidden behind the front of their closed shape.
    const PfxVector3 normal = (b - a).cross(c - a);
    if (normal.dot(a - m_eye) >= 0) return;
    bool onGround = normal.normalized().dot(m_up) > PfxFloat(0.999);
    for (const PfxVector3* p : {&a, &b, &c}) {
      onGround = onGround && std::abs(p->dot(m_up) - m_groundHeight) < m_groundTolerance;
    }
    addTriangle(a, b, c, color, onGround ? kLayerGround : kLayerBodies, 0);
  });
  render.renderShapes(world);
  if (m_drawGrid) addGrid(world);
  if (m_drawContacts) {
    PfxDebugRender contacts;
    contacts.setDrawLength((camera.position - camera.target).norm() * PfxFloat(0.03));
    contacts.setForceScale(0);  // force lines would cover the picture in a heavy scene
    contacts.setDebugRenderPointFunc([this](const PfxVector3& p, const PfxVector3& color) {
      m_overlayPoints.push_back({p, color});
    });
    contacts.setDebugRenderLineFunc(
        [this](const PfxVector3& a, const PfxVector3& b, const PfxVector3& color) {
          m_overlayLines.push_back({a, b, color});
        });
    contacts.renderContact(world);
  }
  std::sort(m_primitives.begin(), m_primitives.end(),
            [](const Primitive& p, const Primitive& q) {
              return p.layer != q.layer ? p.layer < q.layer : p.depth > q.depth;
            });
  m_numDrawnTriangles = static_cast<PfxUInt32>(std::count_if(
      m_primitives.begin(), m_primitives.end(), [](const Primitive& p) { return !p.line; }));
}

PfxInt32 PfxScenePicture::draw(const PfxWorld& world, const std::string& pngPath,
                               std::string* message) {
  PfxSceneCamera camera = m_camera;
  if (!m_hasCamera) {
    const PfxVector3 gravity = world.getParam().gravity;
    const PfxVector3 up = gravity.norm() > PFX_EPSILON ? PfxVector3(-gravity.normalized())
                                                       : PfxVector3::UnitY();
    camera = frameScene(world, up);
  }
  collect(world, camera);

  cairo_surface_t* surface =
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, int(m_width), int(m_height));
  cairo_t* cr = cairo_create(surface);
  cairo_pattern_t* sky = cairo_pattern_create_linear(0, 0, 0, m_height);
  cairo_pattern_add_color_stop_rgb(sky, 0, 0.62, 0.72, 0.84);
  cairo_pattern_add_color_stop_rgb(sky, 1, 0.93, 0.94, 0.95);
  cairo_set_source(cr, sky);
  cairo_paint(cr);
  cairo_pattern_destroy(sky);

  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (const Primitive& p : m_primitives) {
    cairo_set_source_rgb(cr, p.color.x(), p.color.y(), p.color.z());
    cairo_move_to(cr, p.x[0], p.y[0]);
    cairo_line_to(cr, p.x[1], p.y[1]);
    if (p.line) {
      cairo_set_line_width(cr, 1);
      cairo_stroke(cr);
      continue;
    }
    cairo_line_to(cr, p.x[2], p.y[2]);
    cairo_close_path(cr);
    // A thin outline in the fill colour closes the hairline seams between neighbours.
    cairo_set_line_width(cr, 0.6);
    cairo_fill_preserve(cr);
    cairo_stroke(cr);
  }

  auto project = [&](const PfxVector3& p, double& x, double& y) {
    const PfxVector3 v = m_view * (p - m_eye);
    if (-v.z() < m_nearDepth) return false;
    x = PfxFloat(m_width) / 2 + m_focal * v.x() / -v.z();
    y = PfxFloat(m_height) / 2 - m_focal * v.y() / -v.z();
    return true;
  };
  cairo_set_line_width(cr, 1.5);
  for (const OverlayLine& line : m_overlayLines) {
    double x0, y0, x1, y1;
    if (!project(line.a, x0, y0) || !project(line.b, x1, y1)) continue;
    cairo_set_source_rgb(cr, line.color.x(), line.color.y(), line.color.z());
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, x1, y1);
    cairo_stroke(cr);
  }
  const double pointRadius = std::max(2.0, m_height / 320.0);
  for (const OverlayPoint& point : m_overlayPoints) {
    double x, y;
    if (!project(point.position, x, y)) continue;
    cairo_arc(cr, x, y, pointRadius, 0, 2 * PFX_PI);
    cairo_set_source_rgb(cr, point.color.x(), point.color.y(), point.color.z());
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 0.8);
    cairo_stroke(cr);
  }
  cairo_destroy(cr);
  const cairo_status_t status = cairo_surface_write_to_png(surface, pngPath.c_str());
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) {
    if (message) *message = pngPath + ": cannot write the picture: " + cairo_status_to_string(status);
    return PFX_ERR_INVALID_VALUE;
  }
  return PFX_OK;
}

}  // namespace pfx
