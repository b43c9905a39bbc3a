// The one interface every engine of the benchmark sits behind: build a scene with the
// step settings, step it, read the bodies and the joints' anchor points back. Adapters live one per file
// (bench_engine_<name>.cpp); a peer's adapter is compiled only when CMake finds its library.
//
// Settings matched in every engine: time step (dt / substeps per solver step), solver
// iterations, gravity, mass and principal inertia (given explicitly, never recomputed by
// the engine), shape sizes, initial pose and velocities, friction combined as sqrt(a b) and
// restitution as max(a, b) as pfx does, no damping, no sleeping, and the commands of
// joint motors (bench_motors.h: one controller for all, fed by each engine's own states).
//
// Settings that could not be matched:
// - Contact model. pfx, Bullet and ODE solve hard contacts with sequential impulses
//   (projected Gauss-Seidel; pfx solves the normal rows of one manifold as a block, the
//   others row by row); MuJoCo solves soft contacts (solref 0.02 s, solimp default)
//   by convex optimisation with its default Newton solver, so its "iterations" are Newton
//   iterations, it stops early at its default tolerance (1e-8), and resting boxes sink
//   into each other by design.
// - Penetration recovery. pfx: split impulses push an overlap beyond a 5 mm slop out by
//   0.2 of it per step without adding velocity. Bullet: the same (split impulse for every
//   overlap, erp2 0.2, 5 mm linear slop, full turn). ODE: no split impulse; ERP 0.2 as a
//   velocity bias with a 5 mm contact surface layer, global CFM left at ODE's 1e-5 for
//   conditioning. MuJoCo: governed by its soft-contact solref/solimp.
// - Friction cone. pfx: both tangent impulses together clamped to the friction circle of
//   the current normal impulse. Bullet: two tangent rows clamped one by one (a square, up
//   to sqrt(2) more friction diagonally). ODE: dContactApprox1, the same square. MuJoCo:
//   its default pyramidal cone with condim 3 and the maximum of the two geoms' friction,
//   which equals sqrt(a b) only because every scene gives all bodies the same friction.
// - Restitution. MuJoCo has no coefficient of restitution (it is ignored there); the
//   scenes use 0. pfx, Bullet and ODE bounce only above 0.2 m/s of approach.
// - Contact points. pfx keeps at most 4 per pair; ODE is asked for 4 per pair and step;
//   Bullet keeps 4 per persistent manifold; MuJoCo generates its own set every step.
// - Collision margins. Bullet's convex margin (default 4 cm) is lowered to a tenth of the
//   smallest half extent where that is smaller, since thin boxes cannot hold it; pfx adds
//   2 cm of speculative margin; ODE and MuJoCo use none.
// - Tunnelling. pfx always uses speculative contacts. Bullet's continuous collision is
//   switched on for every dynamic body (motion threshold and swept sphere = the shape's
//   inner radius), as a Bullet user facing fast bodies would; ODE and MuJoCo have none.
// - Gyroscopic term. pfx integrates the free rotation with its own exact-momentum
//   integrator; Bullet uses its default implicit gyroscopic term; ODE its default
//   gyroscopic torque; MuJoCo its default semi-implicit Euler integrator.
// - Precision. pfx and Bullet (Debian build) are single precision, ODE and MuJoCo double.
// - Cost of the default solver. MuJoCo 2.2's Newton solver factorises a dense Hessian over
//   all degrees of freedom, so its step time grows with the cube of the number of free
//   bodies in contact; scenes beyond 500 free bodies (rain) are skipped for MuJoCo, and so
//   are scenes whose constraint arrays (njmax x njmax doubles in mjData) would pass 2 GB:
//   the 64 arms and 16 ragdolls of `robots`.
// - Sub-steps. Every engine runs its collision detection again in each sub-step: pfx is
//   stepped N times at dt / N. PfxWorldParam::subStep, which shares one collision
//   detection among the sub-steps, is not what `substeps` measures.
// - Joints. pfx, Bullet (engine `bullet`) and ODE hold bodies together in maximal
//   coordinates, so a joint can open: pfx solves the locked axes of a joint tree directly
//   and corrects positions after integrating; Bullet's btPoint2PointConstraint and
//   btHingeConstraint are rows of its sequential impulse solver with its default joint ERP
//   of 0.2 (split impulses act on contacts only); ODE's ball and hinge joints take the
//   world's ERP 0.2 and CFM 1e-5. MuJoCo and Bullet's Featherstone btMultiBody (engine
//   `bullet_multibody`) move in generalised coordinates: their bodies are nested in a tree
//   and a joint cannot open, so their joint_gap_max is zero by construction (what is
//   reported is rounding). Both integrate the velocity-dependent (Coriolis and centripetal)
//   terms explicitly with their default semi-implicit Euler step; MuJoCo's joints have no
//   damping or armature. Hinge limits (the ragdoll's elbows and knees) are each engine's
//   own: pfx's limit rows, Bullet's btHingeConstraint::setLimit with its default softness,
//   bias and relaxation, ODE's hinge stops with the world's ERP and CFM, MuJoCo's
//   limited range with its default solref and solimp; bullet_multibody's are
//   btMultiBodyJointLimitConstraints. A hinge to the world is made in Bullet against its
//   fixed body. bullet_multibody runs only scenes whose joints form trees hanging
//   from the world and starting at rest (the chains, the arm; not the floating ragdolls of
//   `ragdoll` and `robots`); its links have no damping and no cap
//   on joint speed (Bullet's defaults are 0.04 and 100 rad/s, which would mask a blow-up
//   as a clamped speed), and its contact impulses are not capped either. MuJoCo runs
//   every joint tree, but no closed loops and no jointed bodies that start moving. Bodies
//   held by a joint never collide with each other in any engine; other bodies of the same
//   chain do.
// - Joint motors (the urdf scene). Before each step the benchmark computes every motor's
//   target rate the same way for all engines (reference rate + 10/s x angle error, cut to
//   the URDF velocity limit) and holds it through the step's sub-steps; the torque limit
//   is the URDF effort. pfx: the hinge twist axis's velocity drive (m_drive, m_driveTarget,
//   m_driveMaxForce). Its drive row is iterated with the other bounded rows against the
//   two bodies' own inertia, and the tree's direct solve of the locked axes then spreads
//   its impulse over the arm, so at 10 iterations the shoulder and wrist motors lag and the
//   tracking loop rings at dt >= 1/60 (20-40 iterations track closely). Bullet:
//   btHingeConstraint::enableAngularMotor, bullet_multibody: btMultiBodyJointMotor, both
//   with a velocity target and an impulse bound of effort x sub-step, rows of their
//   iterative solvers (bullet_multibody's in joint space, with the articulation's own
//   inertia). ODE: dParamVel within dParamFMax = effort, rows of QuickStep. MuJoCo has no
//   motor constraint: a velocity actuator, a servo of gain kv = effort / (0.1 x velocity
//   limit) clamped to +-effort, which MuJoCo's default Euler integrator cannot keep stable
//   at these steps, so MuJoCo steps this scene with its implicit integrator (which also
//   treats the velocity-dependent Coriolis terms implicitly). A stiffer servo is not
//   closer: the implicit step linearises it as if it never clamped, and at kv 10 times
//   higher it clamped at every change of command and the arm fell 1-2.5 rad behind. The
//   URDF's joint damping and friction are left out in every engine: pfx's drive row takes
//   their place on a driven axis.
// - Robot geometry (the urdf scene). The shapes are spheres, boxes, capsules and cylinders
//   only: each link gets the box about its centre of mass, along its principal axes, that
//   bounds its collision mesh's vertices, rather than a convex hull that every adapter
//   would have to learn. The arm's meshes are boxes (exact) and 8-sided prisms (the box is
//   21 % larger in cross-section). The gripper's mimic fingers are lumped, closed, into
//   the palm in every engine: Bullet's and ODE's sliders have no mimic coupling, and a
//   finger pair held by pfx's coupling and MuJoCo's equality but free in the others would
//   not be the same arm. The fixed base is the world the first hinge hangs from and has no
//   shape: the shoulder stands on it and the engines cannot all keep a pair without a
//   joint from colliding. Links collide with each other only where an engine has lost
//   its track (Bullet and ODE at dt 1/30).
// - Blow-ups. MuJoCo resets its state to the start when it meets a bad number; the
//   benchmark stops such a run there instead of letting it carry on from the reset. A
//   scene may set a speed limit (the chains: ten times the speed of a free fall from the
//   chain's length); a body beyond it stops the run as blown up. Stopped runs report NaN
//   figures and say on stderr when and why they stopped.
// - Threads. pfx runs on PfxWorldParam::numThreads threads (its oneTBB task manager) and
//   gives the same bits with any number of them. The peers run on one thread, and runs
//   asking them for more are skipped, not faked: Debian's Bullet is built without
//   BT_THREADSAFE (btCreateDefaultTaskScheduler() returns null, so btDiscreteDynamicsWorldMt
//   would run on one thread), ODE steps a world on one thread, and MuJoCo steps one model
//   on one thread.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "bench_scene.h"

namespace pfxbench {

struct EngineSettings {
  double dt = 1.0 / 60;  // time advanced by one step()
  int substeps = 1;      // solver steps of dt / substeps inside one step()
  int iterations = 10;   // solver iterations per solver step
  int threads = 1;
};

struct BodyState {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  Vec3 linearVelocity = Vec3::Zero();   // world frame
  Vec3 angularVelocity = Vec3::Zero();  // world frame
};

// Where the two bodies of a joint carry its anchor point, in world coordinates: on body A
// (or the world point, for a joint to the world) and on body B. They coincide while the
// joint holds; joint_gap_max is the largest distance between them.
struct JointAnchors {
  Vec3 onA = Vec3::Zero();
  Vec3 onB = Vec3::Zero();
};

class Engine {
 public:
  virtual ~Engine() = default;
  // False (with the reason) for a scene this engine cannot run at all here; such runs are
  // skipped and reported, not counted as failures.
  virtual bool supports(const Scene&, const EngineSettings&, std::string& /*reason*/) const {
    return true;
  }
  // Creates every body and joint of the scene; on failure says why in `error`.
  virtual bool build(const Scene& scene, const EngineSettings& settings, std::string& error) = 0;
  // Target rates (rad/s, JointDesc's sign) of the scene's motors, in the order of
  // Scene::motors, held by each engine's own joint motor until the next call; the
  // benchmark calls it before every step of a scene with motors.
  virtual void setMotorRates(const std::vector<double>& rates) = 0;
  // Advances the world by settings.dt; false (with `error`) if the engine failed.
  virtual bool step(std::string& error) = 0;
  // The state of every body, in the scene's order, fixed bodies included.
  virtual void readBodies(std::vector<BodyState>& states) const = 0;
  // The anchors of every joint, in the scene's order.
  virtual void readJointAnchors(std::vector<JointAnchors>& anchors) const = 0;
};

struct EngineInfo {
  const char* name;
  // Null when the engine's library was not found when the benchmark was configured.
  std::unique_ptr<Engine> (*create)();
  int maxThreads;
};

// Every engine the benchmark knows, built or not, in the order of the default sweep.
const std::vector<EngineInfo>& knownEngines();

std::unique_ptr<Engine> createPfxEngine();
std::unique_ptr<Engine> createBulletEngine();
std::unique_ptr<Engine> createBulletMultiBodyEngine();
std::unique_ptr<Engine> createOdeEngine();
std::unique_ptr<Engine> createMujocoEngine();

}  // namespace pfxbench
