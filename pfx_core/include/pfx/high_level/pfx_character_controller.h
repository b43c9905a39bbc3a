// Characters (seed sample 10_character_ctrl): upright capsules that walk where they are
// told, climb steps and walkable slopes, slide down steeper ones, ride moving platforms,
// jump, push loose bodies with a bounded force and are pushed by them.
//
// A character is a real body of the world: an active capsule, frictionless, whose inertia
// is so large that contacts barely turn it, and update() sets it upright again. Everything
// in the world meets it as it meets any body: rays hit it, contacts list it, boxes land on
// it, other characters block it, and the solver's speculative contacts keep it from passing
// through walls and floors at the speeds it can reach (maxSpeed, maxFallSpeed). The
// controller owns no physics: once per step, before PfxWorld::step(), update() asks the
// world where each character's ground and walls are (PfxWorld::queryContacts), runs the
// state machine, and sets each body's velocity, or its position for a step up or a snap
// down to the ground, through PfxWorld::setRigidState.
//
// How it walks. On the ground the controller steers the velocity relative to the ground
// (a keyframe ground's motion at the character, a platform's turn included, is added in
// full, as feet that do not slip; loose bodies and other characters carry nothing, see
// pfx_character_motion.cpp) towards the desired velocity laid onto the ground's plane,
// changing it by at most maxForce / mass * timeStep per step: so maxForce is how hard it
// accelerates and the most it pushes with, and anything that pushes harder moves it. The
// part of gravity along a walkable slope is cancelled, as feet would hold it. Ground is a
// surface within groundProbe below the capsule whose normal is within maxSlope of up (not
// another character: one that lands on a head slides off); after a step on the ground it
// is sought down to maxStepHeight + groundProbe, and the body is moved down onto it, which
// keeps it on stairs and slopes going down; no further than any surface below the capsule
// allows, though, so that the rim of a step beside the feet is not driven into the step's
// side: held up there, gravity acts as in the air and the body slides off the rim. Steeper surfaces of bodies that forces do not
// move (fixed, keyframe) are walls: the desired velocity loses its part into them, so it
// cannot creep up a steep ramp and slides down one. A wall lower than maxStepHeight in
// front of a character on the ground is a step when there is room for the capsule above it
// and a walkable top to stand on: the body is lifted onto it.
//
// States: standing, walking (on the ground, without or with a desired velocity), jumping
// (after a jump, while it rises), falling (in the air), sliding (in the air but against a
// surface too steep to stand on), landing (on the ground after being in the air, for
// landingTime). pfxGetCharacterStateName names them.
#pragma once

#include <vector>

#include "pfx/high_level/pfx_world.h"

namespace pfx {

enum PfxCharacterState : PfxUInt8 {
  kPfxCharacterStanding = 0,
  kPfxCharacterWalking,
  kPfxCharacterJumping,
  kPfxCharacterFalling,
  kPfxCharacterSliding,
  kPfxCharacterLanding,
  kPfxCharacterStateCount
};

const char* pfxGetCharacterStateName(PfxCharacterState state);

// PfxCharacterStatus::groundBodyId in the air.
constexpr PfxUInt32 PFX_CHARACTER_NO_GROUND = 0xffffffffu;

struct PfxCharacterParam {
  PfxFloat radius = PfxFloat(0.3);  // m, > 0
  PfxFloat height = PfxFloat(1.8);  // m, foot to head, > 2 radius
  PfxFloat mass = 80;               // kg, > 0
  // Highest step it climbs (m), in [0, height - 2 radius].
  PfxFloat maxStepHeight = PfxFloat(0.35);
  // Steepest slope it stands and walks on (radians), in [0, 89 degrees].
  PfxFloat maxSlope = PfxFloat(45) * PFX_PI / 180;
  // Largest force with which it changes its own velocity along the ground (N), > 0: its
  // acceleration is maxForce / mass, and it pushes other bodies with no more than this.
  PfxFloat maxForce = 1600;
  // Share of maxForce it steers with in the air, in [0, 1].
  PfxFloat airControl = PfxFloat(0.2);
  PfxFloat jumpSpeed = 5;  // m/s upward added by a jump, >= 0
  // Fastest it walks (m/s), > 0: faster desired velocities are cut down to this length.
  PfxFloat maxSpeed = 10;
  // Fastest it falls (m/s), > 0.
  PfxFloat maxFallSpeed = 50;
  PfxFloat landingTime = PfxFloat(0.1);  // s in the landing state, >= 0
  // How far below the capsule a surface still counts as ground (m), > 0.
  PfxFloat groundProbe = PfxFloat(0.05);
  // The body's contact filters (pfxContactFiltersMatch); its queries use the same ones.
  PfxUInt32 contactFilterSelf = 0xffffffffu;
  PfxUInt32 contactFilterTarget = 0xffffffffu;
};

// PFX_OK, or PFX_ERR_INVALID_VALUE for a parameter outside its documented range.
PfxInt32 pfxCheckCharacterParam(const PfxCharacterParam& param);

struct PfxCharacterStatus {
  PfxVector3 footPosition = PfxVector3::Zero();  // the capsule's lowest point
  PfxVector3 velocity = PfxVector3::Zero();      // of the body, world frame
  PfxCharacterState state = kPfxCharacterFalling;
  PfxFloat timeInState = 0;  // s since the last transition
  // On the ground: the body it stands on and that surface's normal.
  PfxUInt32 groundBodyId = PFX_CHARACTER_NO_GROUND;
  PfxVector3 groundNormal = PfxVector3::Zero();
  PfxUInt32 rigidBodyId = 0;  // the character's body in the world
  PfxUInt32 numSteps = 0;     // steps climbed so far
};

class PfxCharacterController {
 public:
  // Drives characters in `world`, which must outlive the controller. Up is against the
  // world's gravity (+Y without gravity).
  explicit PfxCharacterController(PfxWorld& world);

  // Adds a character standing with its foot at `footPosition`. Rejects what
  // pfxCheckCharacterParam rejects and a non-finite position (PFX_ERR_INVALID_VALUE), and
  // whatever PfxWorld::addRigidBody rejects; nothing changes then. The id is the lowest
  // free one: ids of removed characters are given out again.
  PfxInt32 addCharacter(const PfxCharacterParam& param, const PfxVector3& footPosition,
                        PfxUInt32* outId = nullptr);
  // Takes a character out of play and removes its body from the world
  // (PfxWorld::removeRigidBody): no body, ray or query meets it again. Rejects an unknown id
  // (PFX_ERR_OUT_OF_RANGE) and what the world's removal rejects; nothing changes then.
  PfxInt32 removeCharacter(PfxUInt32 id);

  // The velocity to walk at (m/s, world frame), kept until changed; its part along up is
  // ignored, and a horizontal part faster than maxSpeed, however fast, is cut down to
  // maxSpeed. Rejects an unknown id (PFX_ERR_OUT_OF_RANGE) and a non-finite velocity
  // (PFX_ERR_INVALID_VALUE).
  PfxInt32 setDesiredVelocity(PfxUInt32 id, const PfxVector3& velocity);
  // Jumps at the next update if the character is then on the ground; forgotten otherwise.
  // Rejects an unknown id (PFX_ERR_OUT_OF_RANGE).
  PfxInt32 requestJump(PfxUInt32 id);

  // Rejects an unknown id (PFX_ERR_OUT_OF_RANGE), leaving `out` as it was.
  PfxInt32 getStatus(PfxUInt32 id, PfxCharacterStatus& out) const;
  PfxInt32 getParam(PfxUInt32 id, PfxCharacterParam& out) const;
  bool isCharacter(PfxUInt32 id) const;
  PfxUInt32 getNumCharacters() const { return m_numCharacters; }
  // One more than the largest id in use (ids below it may be free).
  PfxUInt32 getIdLimit() const { return static_cast<PfxUInt32>(m_characters.size()); }

  // Senses and steers every character for the next step; call once before each
  // PfxWorld::step(). Reads the world first and writes it afterwards, so all of a step's
  // queries share one update of the world's query hierarchy. Allocates nothing but in the
  // first call after bodies were added to the world (which sizes its query hierarchy then).
  // Fails only when the world rejects a query or a state (a body whose state went bad);
  // characters are then left as they were from the failing one on.
  PfxInt32 update();

 private:
  struct Character {
    PfxCharacterParam param;
    PfxVector3 desiredVelocity = PfxVector3::Zero();
    PfxCharacterStatus status;
    PfxFloat cosMaxSlope = 1;
    bool live = false;
    bool jumpRequested = false;
  };
  // What update() found for one character, written back after all have been sensed.
  struct Plan {
    PfxVector3 position;
    PfxVector3 velocity;
    bool write = false;
  };
  struct Ground {
    bool found = false;
    PfxFloat drop = 0;  // how far below the capsule (m, negative when overlapping)
    PfxUInt32 bodyId = PFX_CHARACTER_NO_GROUND;
    PfxVector3 normal = PfxVector3::Zero();
  };

  PfxInt32 sense(Character& character, Plan& plan);
  PfxInt32 query(const Character& character, const PfxVector3& center, PfxFloat threshold,
                 PfxUInt32& numContacts);
  Ground findGround(const Character& character, PfxUInt32 numContacts) const;
  PfxFloat clearanceBelow(PfxUInt32 numContacts) const;
  PfxInt32 tryStepUp(const Character& character, const PfxVector3& center,
                     const PfxVector3& direction, PfxFloat& rise);
  PfxVector3 groundVelocity(const Ground& ground, const PfxVector3& center) const;
  PfxVector3 withoutWalls(const Character& character, PfxUInt32 numContacts, PfxVector3 velocity,
                          bool& againstSteep, bool& blockedLow) const;
  void transition(Character& character, PfxCharacterState state) const;
  void advanceState(Character& character, bool jumped, bool onGround, bool rising,
                    bool againstSteep) const;
  PfxVector3 up() const;
  bool isCharacterBody(PfxUInt32 bodyId) const {
    return bodyId < m_characterBodies.size() && m_characterBodies[bodyId];
  }

  PfxWorld& m_world;
  std::vector<Character> m_characters;  // indexed by character id
  std::vector<Plan> m_plans;
  std::vector<PfxQueryContact> m_contacts;
  std::vector<bool> m_characterBodies;  // indexed by rigid body id: held by a live character
  PfxUInt32 m_numCharacters = 0;
};

}  // namespace pfx
