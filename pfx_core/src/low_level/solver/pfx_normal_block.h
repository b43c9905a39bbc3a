// The normal rows of one manifold solved together, as a small projected Gauss-Seidel on
// their coupling matrix K: the points of one face hold a body up jointly, and solving them
// one at a time lets it rock between them, which tall stacks turn into sway. Used by the
// iterations (K of both bodies) and by shock propagation (K of the upper body alone).
#pragma once

#include <algorithm>

#include "pfx/base_level/collision/pfx_contact_manifold.h"

namespace pfx {

using PfxNormalCoupling = PfxFloat[PFX_NUM_CONTACTS_PER_MANIFOLD][PFX_NUM_CONTACTS_PER_MANIFOLD];

// Sweeps of the small problem; it converges in a few.
constexpr int kPfxNormalBlockSweeps = 6;

// `residual` is each row's target velocity minus its current velocity; `impulse` is the
// accumulated impulse, kept at zero or above and updated; `delta` receives the change to
// apply. N is known at compile time so that the loops unroll: this is the solver's
// innermost loop.
template <PfxUInt32 N>
void pfxSweepNormalBlock(const PfxNormalCoupling& k, const PfxFloat* residual,
                         PfxFloat* impulse, PfxFloat* delta) {
  PfxFloat inverseDiagonal[N];
  PfxFloat remaining[N];  // residual minus K * delta
  for (PfxUInt32 i = 0; i < N; ++i) {
    inverseDiagonal[i] = k[i][i] > 0 ? PfxFloat(1) / k[i][i] : PfxFloat(0);
    remaining[i] = residual[i];
    delta[i] = 0;
  }
  for (int sweep = 0; sweep < kPfxNormalBlockSweeps; ++sweep) {
    bool changed = false;
    for (PfxUInt32 i = 0; i < N; ++i) {
      const PfxFloat updated =
          std::max(impulse[i] + delta[i] + remaining[i] * inverseDiagonal[i], PfxFloat(0)) -
          impulse[i];
      const PfxFloat change = updated - delta[i];
      delta[i] = updated;
      changed = changed || change != 0;
      for (PfxUInt32 j = 0; j < N; ++j) remaining[j] -= k[j][i] * change;
    }
    // A sweep that changed no impulse left every residual as it was, so the sweeps after
    // it would repeat it: stop. Not after the first, which may have turned a residual
    // into NaN through a NaN or infinite K whatever the changes, where the next sweep
    // would carry that into the impulses. A manifold of one point (most of a pile of
    // spheres) settles after two or three of the six.
    if (!changed && sweep > 0) break;
  }
  for (PfxUInt32 i = 0; i < N; ++i) impulse[i] += delta[i];
}

inline void pfxSolveNormalBlock(PfxUInt32 numRows, const PfxNormalCoupling& k,
                                const PfxFloat* residual, PfxFloat* impulse, PfxFloat* delta) {
  switch (numRows) {
    case 1: pfxSweepNormalBlock<1>(k, residual, impulse, delta); break;
    case 2: pfxSweepNormalBlock<2>(k, residual, impulse, delta); break;
    case 3: pfxSweepNormalBlock<3>(k, residual, impulse, delta); break;
    case 4: pfxSweepNormalBlock<4>(k, residual, impulse, delta); break;
    default: break;
  }
}

}  // namespace pfx
