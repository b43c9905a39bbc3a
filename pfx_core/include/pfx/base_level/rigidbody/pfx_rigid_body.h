// Physical attributes of one rigid body: mass, inertia, friction, restitution.
#pragma once

#include <limits>

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

// The masses (kg) and principal moments of inertia (kg m^2) an active body may have. Within
// them, the largest impulse a contact or joint between the heaviest and the lightest body can
// carry at the largest speed (kPfxMaxLinearSpeed) still changes a velocity by a finite amount
// in float; a mass of 1e-45 kg had an infinite inverse, and its first step turned it NaN.
constexpr PfxFloat kPfxMinMass = PfxFloat(1e-12);
constexpr PfxFloat kPfxMaxMass = PfxFloat(1e12);
constexpr PfxFloat kPfxMinMoment = PfxFloat(1e-18);
constexpr PfxFloat kPfxMaxMoment = PfxFloat(1e18);
// The smallest principal moment an active body may have, as a fraction of its largest: 8
// times the precision's epsilon. Below it the moment is lost in rounding once the tensor is
// turned into the world frame, and the world's inverse inertia may no longer be positive:
// a bar of 0.0308 kg m^2 across turned NaN in its first step on a hinge with 2.4e-7 of that
// about its length, and stepped 200 times from 4.2e-7 of it (float).
constexpr PfxFloat kPfxMinMomentRatio = 8 * std::numeric_limits<PfxFloat>::epsilon();
// How far the largest principal moment may exceed the sum of the other two, relative to
// it: each moment is a sum of m (y^2 + z^2) and the like over the body, so the largest is
// at most the sum of the others, equal for a flat body. Files giving moments to three
// significant digits can break the rule by up to 1e-2 that way; 7.0e3, 0.031 and 0.031 kg
// m^2 in a fuzzed file broke it by far.
constexpr PfxFloat kPfxMomentSumTolerance = PfxFloat(1e-2);

class PfxRigidBody {
 public:
  void reset();

  PfxFloat getMass() const { return m_mass; }
  PfxFloat getMassInv() const { return m_massInv; }
  // Inertia tensor about the centre of mass, in the body frame.
  const PfxMatrix3& getInertia() const { return m_inertia; }
  const PfxMatrix3& getInertiaInv() const { return m_inertiaInv; }
  PfxFloat getFriction() const { return m_friction; }
  PfxFloat getRestitution() const { return m_restitution; }

  // Stores the mass as given; isValid() tells whether it can drive an active body.
  void setMass(PfxFloat mass);
  void setInertia(const PfxMatrix3& inertia);
  void setFriction(PfxFloat friction) { m_friction = friction; }
  void setRestitution(PfxFloat restitution) { m_restitution = restitution; }

  // Mass within [kPfxMinMass, kPfxMaxMass], symmetric inertia whose principal moments lie
  // within [kPfxMinMoment, kPfxMaxMoment], are those of a rigid body (the largest at most the
  // sum of the other two, to kPfxMomentSumTolerance) and whose smallest is not lost in
  // rounding beside the largest (at least kPfxMinMomentRatio times it), friction >= 0,
  // 0 <= restitution <= 1.
  bool isValid() const { return problem() == nullptr; }
  // Which of the rules above the body breaks, in words (the loaders put it in their
  // errors), or nullptr if it keeps them all.
  const char* problem() const;

 private:
  PfxMatrix3 m_inertia;
  PfxMatrix3 m_inertiaInv;
  PfxFloat m_mass;
  PfxFloat m_massInv;
  PfxFloat m_friction;
  PfxFloat m_restitution;
};

}  // namespace pfx
