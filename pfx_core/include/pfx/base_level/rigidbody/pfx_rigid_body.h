// Physical attributes of one rigid body: mass, inertia, friction, restitution.
#pragma once

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
  // within [kPfxMinMoment, kPfxMaxMoment] and whose smallest is not lost in rounding beside
  // the largest (at least the largest times epsilon), friction >= 0, 0 <= restitution <= 1.
  bool isValid() const;

 private:
  PfxMatrix3 m_inertia;
  PfxMatrix3 m_inertiaInv;
  PfxFloat m_mass;
  PfxFloat m_massInv;
  PfxFloat m_friction;
  PfxFloat m_restitution;
};

}  // namespace pfx
