// A picture of a world, drawn offscreen with cairo through PfxDebugRender's callbacks: a
// perspective camera, flat-shaded triangles sorted back to front (the painter's
// algorithm), a grid on the ground, and the contact points on top; written as PNG.
#pragma once

#include <string>
#include <vector>

#include "pfx/high_level/pfx_world.h"

namespace pfx {

struct PfxSceneCamera {
  PfxVector3 position = PfxVector3(5, -5, 4);
  PfxVector3 target = PfxVector3::Zero();
  PfxVector3 up = PfxVector3::UnitZ();
  PfxFloat fieldOfView = 40;  // vertical, degrees
};

class PfxScenePicture {
 public:
  // Sizes are clamped to 16..8192 pixels.
  explicit PfxScenePicture(PfxUInt32 width = 1280, PfxUInt32 height = 960);

  // A camera that sees every body that moves (every body when none moves, so that a
  // ground plane does not shrink the robot on it to a dot), from in front, to the right
  // and above, with `up` up.
  static PfxSceneCamera frameScene(const PfxWorld& world, const PfxVector3& up,
                                   PfxFloat fieldOfView = 40);

  // Rejects a non-finite camera, a position on the target, an up along the view, or a field
  // of view outside (1, 170) degrees (PFX_ERR_INVALID_VALUE); keeps the old one then.
  // Without a camera, draw() frames the scene with up against gravity.
  PfxInt32 setCamera(const PfxSceneCamera& camera);
  // Direction the light travels (need not be unit length). Rejects zero and NaN.
  PfxInt32 setLightDirection(const PfxVector3& direction);
  void setDrawGrid(bool draw) { m_drawGrid = draw; }
  void setDrawContacts(bool draw) { m_drawContacts = draw; }

  // Draws the world and writes the PNG. On failure returns an error code and, when
  // `message` is given, says why (the file that could not be written).
  PfxInt32 draw(const PfxWorld& world, const std::string& pngPath, std::string* message = nullptr);

  // What the last draw put in the picture (after culling): for tests and reports.
  PfxUInt32 getNumDrawnTriangles() const { return m_numDrawnTriangles; }
  const PfxSceneCamera& getUsedCamera() const { return m_usedCamera; }

 private:
  // What is drawn first: the ground (triangles lying in the grid's plane, facing up), then
  // the grid on it, then everything else back to front.
  enum Layer : PfxUInt8 { kLayerGround = 0, kLayerGrid, kLayerBodies };
  // A shaded triangle or a grid segment, projected to pixels, with its distance from the eye.
  struct Primitive {
    PfxFloat depth;
    PfxFloat x[3], y[3];
    PfxVector3 color;
    PfxUInt8 layer;
    bool line;
  };
  void collect(const PfxWorld& world, const PfxSceneCamera& camera);
  void addTriangle(const PfxVector3& a, const PfxVector3& b, const PfxVector3& c,
                   const PfxVector3& color, Layer layer, int level);
  void addGrid(const PfxWorld& world);

  PfxUInt32 m_width;
  PfxUInt32 m_height;
  PfxSceneCamera m_camera;
  bool m_hasCamera = false;
  PfxSceneCamera m_usedCamera;
  PfxVector3 m_light = PfxVector3(-0.35f, 0.45f, -1).normalized();
  bool m_drawGrid = true;
  bool m_drawContacts = true;
  PfxUInt32 m_numDrawnTriangles = 0;

  // The view of the draw in progress.
  PfxMatrix3 m_view;  // rows: right, up, back (camera looks along -back)
  PfxVector3 m_eye;
  PfxFloat m_focal = 1;    // pixels per unit of tangent
  PfxFloat m_nearDepth = PfxFloat(0.01);
  PfxVector3 m_up;
  PfxFloat m_groundHeight = 0;     // of the grid's plane along m_up
  PfxFloat m_groundTolerance = 0;  // a triangle this close to the plane lies in it
  std::vector<Primitive> m_primitives;
  // Drawn over everything, in the debug render's colours.
  struct OverlayLine {
    PfxVector3 a, b, color;
  };
  struct OverlayPoint {
    PfxVector3 position, color;
  };
  std::vector<OverlayLine> m_overlayLines;
  std::vector<OverlayPoint> m_overlayPoints;
};

}  // namespace pfx
