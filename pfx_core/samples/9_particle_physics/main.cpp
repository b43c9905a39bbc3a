// Sample 9_particle_physics: particles held together by distance and angle constraints
// (seed sample 9), in three scenes that print what they measure and exit non-zero when a
// check fails. (1) A cloth falls onto a sphere and a box and drapes over them. (2) Hair:
// strands rooted on a keyframe head that turns a quarter turn and back. (3) A rope tied to
// the world with a weight at its end swings into a row of boxes and knocks them over.
#include <cmath>
#include <cstdio>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_debug_render.h"

using namespace pfx;

namespace {

constexpr PfxFloat kPi = PfxFloat(3.14159265358979323846);

void addFloor(PfxWorld& world) {
  PfxBodyInit floor;
  floor.mass = 0;
  floor.position = PfxVector3(0, -0.5f, 0);
  pfxAddBody(world, pfxMakeShape(PfxBox(20, 0.5f, 20)), floor);
}

PfxWorldParam particleParam() {
  PfxWorldParam param;
  param.subStep = 8;
  return param;
}

bool clothScene() {
  PfxWorld world;
  world.initialize(particleParam());
  addFloor(world);
  PfxBodyInit fixed;
  fixed.mass = 0;
  const PfxVector3 sphereCenter(-0.4f, 0.3f, 0);
  const PfxFloat sphereRadius = 0.3f;
  fixed.position = sphereCenter;
  pfxAddBody(world, pfxMakeShape(PfxSphere(sphereRadius)), fixed);
  const PfxVector3 boxCenter(0.45f, 0.25f, 0), boxHalf(0.25f, 0.25f, 0.25f);
  fixed.position = boxCenter;
  pfxAddBody(world, pfxMakeShape(PfxBox(boxHalf)), fixed);

  PfxParticleGroupBuilder cloth;
  PfxParticleGroupBuilder::Material m;
  m.particleMass = 0.002f;
  m.radius = 0.02f;
  m.friction = 0.4f;
  m.bendCompliance = 0.2f;
  cloth.addCloth(PfxVector3(-0.9f, 1.0f, -0.6f), PfxVector3(1.8f, 0, 0), PfxVector3(0, 0, 1.2f),
                 36, 24, m);
  cloth.linearDamping = 0.2f;
  PfxUInt32 id = 0;
  if (world.addParticleGroup(cloth.desc(), &id) != PFX_OK) return false;

  PfxFloat intoSphere = 0, intoBox = 0, intoFloor = 0;
  int steps = 0;
  for (; steps < 60 * 8 && !world.getParticleGroup(id)->asleep; ++steps) {
    if (world.step() != PFX_OK) return false;
    for (const PfxParticle& p : world.getParticleGroup(id)->particles) {
      intoSphere = std::max(intoSphere, sphereRadius + p.m_radius - (p.m_position - sphereCenter).norm());
      const PfxVector3 q = (p.m_position - boxCenter).cwiseAbs() - boxHalf;
      const PfxFloat boxDistance = q.cwiseMax(PfxFloat(0)).norm() + std::min(q.maxCoeff(), PfxFloat(0));
      intoBox = std::max(intoBox, p.m_radius - boxDistance);
      intoFloor = std::max(intoFloor, p.m_radius - p.m_position.y());
    }
  }
  // The cloth did not pass through itself: no two of its particles overlap (a particle's
  // radius, 0.39 of the spacing, leaves no gap in the sheet another particle could pass).
  const std::vector<PfxParticle>& particles = world.getParticleGroup(id)->particles;
  PfxFloat selfOverlap = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    for (std::size_t j = i + 1; j < particles.size(); ++j) {
      const PfxFloat gap = (particles[i].m_position - particles[j].m_position).norm() -
                           particles[i].m_radius - particles[j].m_radius;
      selfOverlap = std::max(selfOverlap, -gap);
    }
  }
  // Count what the cloth's triangles look like to a renderer, through the debug render.
  PfxUInt32 triangles = 0;
  PfxDebugRender render;
  render.setDebugRenderTriangleFunc([&](const PfxVector3&, const PfxVector3&, const PfxVector3&,
                                        const PfxVector3&, PfxUInt32) { ++triangles; });
  render.renderParticles(world);
  const PfxWorldStats& stats = world.getStats();
  std::printf("cloth: %u particles over a sphere and a box, %s after %.2f s; deepest into the "
              "sphere %.2f mm, the box %.2f mm, the floor %.2f mm, into itself %.2f mm; "
              "%u triangles drawn; "
              "particle stages %.2f ms in the last step\n",
              stats.numParticles, world.getParticleGroup(id)->asleep ? "asleep" : "still moving",
              steps / 60.0, 1000 * intoSphere, 1000 * intoBox, 1000 * intoFloor,
              1000 * selfOverlap, triangles,
              1000 * (stats.stageSeconds[kPfxStageIntegrateParticles] +
                      stats.stageSeconds[kPfxStageSolveParticleConstraints] +
                      stats.stageSeconds[kPfxStageUpdateParticles]));
  return world.getParticleGroup(id)->asleep && intoSphere < 0.005f && intoBox < 0.005f &&
         intoFloor < 0.005f && selfOverlap < 0.005f && triangles == 2 * 35 * 23;
}

bool hairScene() {
  PfxWorld world;
  world.initialize(particleParam());
  PfxBodyInit headInit;
  headInit.motionType = kPfxMotionTypeKeyframe;
  headInit.position = PfxVector3(0, 1.6f, 0);
  const PfxFloat headRadius = 0.1f;
  PfxUInt32 head = 0;
  pfxAddBody(world, pfxMakeShape(PfxSphere(headRadius)), headInit, &head);

  // Strands rooted on the crown and the back of the head, each a root particle pinned to
  // the head, a second held a little further out (so that the strand leaves the scalp),
  // then a soft-bending chain.
  PfxParticleGroupBuilder hair;
  PfxParticleGroupBuilder::Material m;
  m.particleMass = 0.0005f;
  m.radius = 0.005f;
  m.bendCompliance = 200.0f;
  m.contactFilterSelf = 2;
  m.contactFilterTarget = ~2u;  // strands touch the head, not each other
  constexpr int kStrands = 24, kPerStrand = 12;
  for (int s = 0; s < kStrands; ++s) {
    const PfxFloat around = 2 * kPi * s / kStrands;
    const PfxFloat up = 0.2f + 0.5f * (s % 3) / 2;
    const PfxVector3 dir(std::cos(around) * std::cos(up), std::sin(up), std::sin(around) * std::cos(up));
    const PfxVector3 root = dir * (headRadius + m.radius);
    const PfxUInt32 first = hair.addRope(headInit.position + root,
                                         headInit.position + root + dir * 0.22f, kPerStrand, m);
    hair.pinToBody(first, head, root);
    hair.pinToBody(first + 1, head, root + dir * (0.22f / (kPerStrand - 1)));
    hair.tetherRope(first, kPerStrand, first);
  }
  hair.linearDamping = 0.5f;
  hair.iteration = 4;
  PfxUInt32 id = 0;
  if (world.addParticleGroup(hair.desc(), &id) != PFX_OK) return false;

  PfxFloat worstGap = 0, intoHead = 0, worstStretch = 0;
  const int turnSteps = 60;
  for (int step = 0; step < 4 * turnSteps; ++step) {
    // A quarter turn in 1 s, back in the next, then held.
    const PfxFloat t = std::min(PfxFloat(step + 1) / turnSteps, PfxFloat(2));
    const PfxFloat angle = 0.5f * kPi * (t <= 1 ? t : 2 - t);
    world.setKeyframeTarget(head, headInit.position,
                            PfxQuat(Eigen::AngleAxis<PfxFloat>(angle, PfxVector3::UnitY())));
    if (world.step() != PFX_OK) return false;
    const PfxRigidState& h = world.getRigidState(head);
    const PfxParticleGroup& g = *world.getParticleGroup(id);
    for (const PfxParticlePin& pin : g.pins) {
      const PfxVector3 anchor = h.getPosition() + h.getOrientation() * pin.m_anchor;
      worstGap = std::max(worstGap, (g.particles[pin.m_particle].m_position - anchor).norm());
    }
    for (const PfxParticle& p : g.particles) {
      intoHead = std::max(intoHead, headRadius + p.m_radius - (p.m_position - h.getPosition()).norm());
    }
    for (const PfxParticleDistanceConstraint& c : g.distanceConstraints) {
      const PfxFloat length = (g.particles[c.m_particleA].m_position - g.particles[c.m_particleB].m_position).norm();
      worstStretch = std::max(worstStretch, length / c.m_restLength - 1);
    }
  }
  // The strands swung with the head and hang down around it at the end.
  const PfxParticleGroup& g = *world.getParticleGroup(id);
  int below = 0;
  for (int s = 0; s < kStrands; ++s) {
    below += g.particles[s * kPerStrand + kPerStrand - 1].m_position.y() <
                     g.particles[s * kPerStrand].m_position.y()
                 ? 1
                 : 0;
  }
  std::printf("hair: %d strands of %d particles on a head turning a quarter turn and back; "
              "largest gap at the roots %.3f mm, deepest into the head %.2f mm, largest "
              "stretch %.2f%%, %d of %d tips hanging below their roots\n",
              kStrands, kPerStrand, 1000 * worstGap, 1000 * intoHead, 100 * worstStretch, below,
              kStrands);
  return worstGap < 0.001f && intoHead < 0.003f && worstStretch < 0.05f && below == kStrands;
}

bool ropeScene() {
  PfxWorld world;
  world.initialize(particleParam());
  addFloor(world);
  // A row of light boxes standing on the floor where the weight swings through.
  PfxUInt32 boxes[4];
  for (int i = 0; i < 4; ++i) {
    PfxBodyInit box;
    box.mass = 0.2f;
    box.position = PfxVector3(0.0f, 0.15f, -0.3f + 0.2f * i);
    pfxAddBody(world, pfxMakeShape(PfxBox(0.05f, 0.15f, 0.05f)), box, &boxes[i]);
  }
  // The weight: a 2 kg ball held out to the side at the rope's length.
  const PfxVector3 pin(0, 1.6f, 0);
  const PfxFloat length = 1.2f;
  PfxBodyInit ball;
  ball.mass = 2;
  ball.position = pin + PfxVector3(-length - 0.1f, 0, 0);
  PfxUInt32 weight = 0;
  pfxAddBody(world, pfxMakeShape(PfxSphere(0.1f)), ball, &weight);

  PfxParticleGroupBuilder rope;
  PfxParticleGroupBuilder::Material m;
  m.particleMass = 0.01f;
  m.radius = 0.01f;
  m.contactFilterSelf = 2;
  m.contactFilterTarget = ~2u;
  rope.addRope(pin, pin + PfxVector3(-length, 0, 0), 25, m);
  rope.setMass(0, 0);  // tied to the world
  rope.tetherRope(0, 25, 0);
  rope.pinToBody(24, weight, PfxVector3(0.1f, 0, 0));
  rope.tetherBody(weight, PfxVector3(0.1f, 0, 0), 0, length);
  rope.iteration = 2;
  PfxUInt32 id = 0;
  if (world.addParticleGroup(rope.desc(), &id) != PFX_OK) return false;

  PfxFloat worstStretch = 0;
  for (int step = 0; step < 60 * 4; ++step) {
    if (world.step() != PFX_OK) return false;
    const PfxRigidState& w = world.getRigidState(weight);
    const PfxVector3 tie = w.getPosition() + w.getOrientation() * PfxVector3(0.1f, 0, 0);
    worstStretch = std::max(worstStretch, (tie - pin).norm() / length - 1);
  }
  int knocked = 0;
  for (PfxUInt32 b : boxes) {
    const PfxRigidState& s = world.getRigidState(b);
    const PfxFloat tilt = 2 * std::acos(std::min(PfxFloat(1), std::abs(s.getOrientation().w())));
    knocked += (tilt > 0.5f || (s.getPosition() - PfxVector3(0, 0.15f, s.getPosition().z())).norm() > 0.1f) ? 1 : 0;
  }
  std::printf("rope: a 2 kg weight on a 1.2 m rope of 25 particles swung into 4 boxes: %d knocked "
              "over or away; the rope stretched %.2f%% at most\n",
              knocked, 100 * worstStretch);
  return knocked >= 2 && worstStretch < 0.03f;
}

}  // namespace

int main() {
  const bool cloth = clothScene();
  const bool hair = hairScene();
  const bool rope = ropeScene();
  std::printf("%s\n", cloth && hair && rope ? "all checks passed" : "a check FAILED");
  return cloth && hair && rope ? 0 : 1;
}
