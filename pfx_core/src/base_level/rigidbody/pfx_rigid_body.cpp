#include "pfx/base_level/rigidbody/pfx_rigid_body.h"

#include <Eigen/Eigenvalues>
#include <cstring>
#include <limits>

namespace pfx {

void PfxRigidBody::reset() {
  std::memset(static_cast<void*>(this), 0, sizeof(*this));
  m_mass = 1;
  m_massInv = 1;
  m_inertia.setIdentity();
  m_inertiaInv.setIdentity();
  m_friction = 0.6f;
  m_restitution = 0;
}

void PfxRigidBody::setMass(PfxFloat mass) {
  m_mass = mass;
  m_massInv = (mass > 0 && pfxIsFinite(mass)) ? PfxFloat(1) / mass : PfxFloat(0);
}

void PfxRigidBody::setInertia(const PfxMatrix3& inertia) {
  m_inertia = inertia;
  const Eigen::FullPivLU<PfxMatrix3> lu(inertia);
  m_inertiaInv = (inertia.allFinite() && lu.isInvertible()) ? PfxMatrix3(lu.inverse())
                                                              : PfxMatrix3::Zero();
}

bool PfxRigidBody::isValid() const {
  if (!(m_mass >= kPfxMinMass && m_mass <= kPfxMaxMass)) return false;
  if (!m_inertia.allFinite()) return false;
  if ((m_inertia - m_inertia.transpose()).cwiseAbs().maxCoeff() >
      PfxFloat(1e-4) * m_inertia.cwiseAbs().maxCoeff()) {
    return false;
  }
  const Eigen::SelfAdjointEigenSolver<PfxMatrix3> eig(m_inertia, Eigen::EigenvaluesOnly);
  // A principal moment below the largest times the precision's epsilon is lost in rounding
  // when the tensor is turned into the world frame; its inverse (7e37 for the 1.4e-38 of a
  // fuzzed saved file) sent the solver's impulses to infinity.
  const PfxFloat smallest = eig.eigenvalues().minCoeff(), largest = eig.eigenvalues().maxCoeff();
  if (!(smallest > largest * std::numeric_limits<PfxFloat>::epsilon()) ||
      !(smallest >= kPfxMinMoment && largest <= kPfxMaxMoment)) {
    return false;
  }
  return m_friction >= 0 && pfxIsFinite(m_friction) && m_restitution >= 0 &&
         m_restitution <= 1;
}

}  // namespace pfx
