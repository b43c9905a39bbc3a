// The characters scene on pfx: the course in a PfxWorld, one PfxCharacterController
// character per walker. Sleep is off, as in every engine of pfx_bench.
#include "bench_characters.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_character_controller.h"

namespace pfxbench {

namespace {

using namespace pfx;

PfxVector3 toPfx(const Vec3& v) { return v.cast<PfxFloat>(); }
PfxQuat toPfx(const Quat& q) { return q.cast<PfxFloat>(); }

class PfxCharacterEngine : public CharacterEngine {
 public:
  bool build(const CharacterCourse& course, double dt, std::string& error) override {
    PfxWorldParam param;
    param.timeStep = PfxFloat(dt);
    param.gravity = PfxVector3(0, PfxFloat(-kCharacterGravity), 0);
    param.worldExtent = toPfx(course.halfExtent);
    param.enableSleep = false;
    PfxInt32 code = m_world.initialize(param);
    auto add = [&](const CourseBox& box, PfxFloat mass, PfxMotionType type, PfxUInt32* id) {
      if (code != PFX_OK) return;
      PfxBodyInit init;
      init.position = toPfx(box.center);
      init.orientation = toPfx(box.orientation);
      init.mass = mass;
      init.motionType = type;
      code = pfxAddBody(m_world,
                        pfxMakeShape(PfxBox(PfxFloat(box.half.x()), PfxFloat(box.half.y()),
                                            PfxFloat(box.half.z()))),
                        init, id);
    };
    for (const CourseBox& box : course.fixedBoxes) add(box, 0, kPfxMotionTypeActive, nullptr);
    m_platforms.resize(course.platforms.size());
    for (std::size_t i = 0; i < course.platforms.size(); ++i) {
      add(course.platforms[i], 500, kPfxMotionTypeKeyframe, &m_platforms[i]);
    }
    for (const CourseBox& box : course.looseBoxes) {
      add(box, PfxFloat(kLooseBoxMass), kPfxMotionTypeActive, nullptr);
    }
    if (code != PFX_OK) {
      error = std::string("building the course: ") + pfxErrorString(code);
      return false;
    }
    m_controller = std::make_unique<PfxCharacterController>(m_world);
    PfxCharacterParam character;
    character.radius = PfxFloat(kCharacterRadius);
    character.height = PfxFloat(kCharacterHeight);
    character.maxStepHeight = PfxFloat(kCharacterStepHeight);
    character.maxSlope = PfxFloat(kCharacterMaxSlopeDegrees * 3.14159265358979323846 / 180);
    character.jumpSpeed = PfxFloat(kCharacterJumpSpeed);
    character.maxFallSpeed = PfxFloat(kCharacterMaxFallSpeed);
    m_characters.resize(course.starts.size());
    for (std::size_t i = 0; i < course.starts.size(); ++i) {
      code = m_controller->addCharacter(character, toPfx(course.starts[i]), &m_characters[i]);
      if (code != PFX_OK) {
        error = std::string("adding a character: ") + pfxErrorString(code);
        return false;
      }
    }
    return true;
  }

  void movePlatform(int index, const Vec3& position, const Quat& orientation) override {
    m_world.setKeyframeTarget(m_platforms[index], toPfx(position), toPfx(orientation));
  }

  void setDesiredVelocity(int character, const Vec3& velocity) override {
    m_controller->setDesiredVelocity(m_characters[character], toPfx(velocity));
  }

  void jump(int character) override { m_controller->requestJump(m_characters[character]); }

  bool step(std::string& error) override {
    PfxInt32 code = m_controller->update();
    if (code == PFX_OK) code = m_world.step();
    if (code != PFX_OK) error = pfxErrorString(code);
    return code == PFX_OK;
  }

  Vec3 foot(int character) const override {
    PfxCharacterStatus status;
    m_controller->getStatus(m_characters[character], status);
    return status.footPosition.cast<double>();
  }

 private:
  PfxWorld m_world;
  std::unique_ptr<PfxCharacterController> m_controller;
  std::vector<PfxUInt32> m_platforms;
  std::vector<PfxUInt32> m_characters;
};

}  // namespace

std::unique_ptr<CharacterEngine> makePfxCharacterEngine() {
  return std::make_unique<PfxCharacterEngine>();
}

}  // namespace pfxbench
