// Three-vectors of the contact sweep's inner loop held in registers. In a float build on
// x86-64 a vector is one SSE2 register (SSE2 is the baseline there), and every operation
// is, lane for lane, the one Eigen performs on a PfxVector3, in the same order (a dot
// product is x + (y + z), as Eigen's unrolled sum; a matrix times a vector takes the dot
// products of its rows so), so the results are the same bits, in fewer instructions and
// without the calls GCC leaves Eigen's 3x3 products in. Other builds
// (double, other processors) hold a PfxVector3 and use Eigen itself.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

#if defined(__SSE2__) && !defined(PFX_DOUBLE)
#define PFX_SOLVER_VEC3_SSE 1
#include <emmintrin.h>
#endif

namespace pfx {

#ifdef PFX_SOLVER_VEC3_SSE

// x, y, z in the three low lanes; the fourth is zero after a load and is never read.
struct PfxSolverVec3 {
  __m128 v;
};

// Exactly three floats: a PfxVector3 may end its allocation.
inline __m128 pfxLoadFloat3(const float* xyz) {
  // __m64 may alias anything, a double may not alias floats.
  const __m128 xy = _mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(xyz));
  return _mm_movelh_ps(xy, _mm_load_ss(xyz + 2));
}

inline PfxSolverVec3 pfxLoadVec3(const PfxVector3& a) { return {pfxLoadFloat3(a.data())}; }

inline void pfxStoreVec3(PfxVector3& out, PfxSolverVec3 a) {
  _mm_storel_pi(reinterpret_cast<__m64*>(out.data()), a.v);
  _mm_store_ss(out.data() + 2, _mm_movehl_ps(a.v, a.v));
}

inline PfxSolverVec3 operator+(PfxSolverVec3 a, PfxSolverVec3 b) { return {_mm_add_ps(a.v, b.v)}; }
inline PfxSolverVec3 operator-(PfxSolverVec3 a, PfxSolverVec3 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline PfxSolverVec3 operator*(PfxSolverVec3 a, PfxFloat s) {
  return {_mm_mul_ps(a.v, _mm_set1_ps(s))};
}
inline PfxSolverVec3 operator*(PfxFloat s, PfxSolverVec3 a) {
  return {_mm_mul_ps(_mm_set1_ps(s), a.v)};
}

inline PfxSolverVec3 pfxZeroVec3() { return {_mm_setzero_ps()}; }

// a x b = (a.y b.z - a.z b.y, a.z b.x - a.x b.z, a.x b.y - a.y b.x).
inline PfxSolverVec3 pfxCross(PfxSolverVec3 a, PfxSolverVec3 b) {
  const __m128 aYzx = _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(3, 0, 2, 1));
  const __m128 bZxy = _mm_shuffle_ps(b.v, b.v, _MM_SHUFFLE(3, 1, 0, 2));
  const __m128 aZxy = _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(3, 1, 0, 2));
  const __m128 bYzx = _mm_shuffle_ps(b.v, b.v, _MM_SHUFFLE(3, 0, 2, 1));
  return {_mm_sub_ps(_mm_mul_ps(aYzx, bZxy), _mm_mul_ps(aZxy, bYzx))};
}

inline PfxFloat pfxDot(PfxSolverVec3 a, PfxSolverVec3 b) {
  const __m128 p = _mm_mul_ps(a.v, b.v);
  const __m128 y = _mm_shuffle_ps(p, p, _MM_SHUFFLE(1, 1, 1, 1));
  const __m128 z = _mm_movehl_ps(p, p);
  return _mm_cvtss_f32(_mm_add_ss(p, _mm_add_ss(y, z)));
}

// A 3x3 matrix (Eigen's column-major storage) as its three columns.
struct PfxSolverMat3 {
  __m128 c0, c1, c2;
};

inline PfxSolverMat3 pfxLoadMat3(const PfxMatrix3& m) {
  return {pfxLoadFloat3(m.data()), pfxLoadFloat3(m.data() + 3), pfxLoadFloat3(m.data() + 6)};
}

// Row i of m times a is m(i,0) a.x + (m(i,1) a.y + m(i,2) a.z), as Eigen sums it.
inline PfxSolverVec3 operator*(const PfxSolverMat3& m, PfxSolverVec3 a) {
  const __m128 x = _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(0, 0, 0, 0));
  const __m128 y = _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(1, 1, 1, 1));
  const __m128 z = _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(2, 2, 2, 2));
  return {_mm_add_ps(_mm_mul_ps(m.c0, x),
                     _mm_add_ps(_mm_mul_ps(m.c1, y), _mm_mul_ps(m.c2, z)))};
}

#else

using PfxSolverVec3 = PfxVector3;
using PfxSolverMat3 = PfxMatrix3;

inline PfxSolverVec3 pfxLoadVec3(const PfxVector3& a) { return a; }
inline void pfxStoreVec3(PfxVector3& out, const PfxSolverVec3& a) { out = a; }
inline PfxSolverVec3 pfxZeroVec3() { return PfxVector3::Zero(); }
inline PfxSolverVec3 pfxCross(const PfxSolverVec3& a, const PfxSolverVec3& b) { return a.cross(b); }
inline PfxFloat pfxDot(const PfxSolverVec3& a, const PfxSolverVec3& b) { return a.dot(b); }
inline const PfxSolverMat3& pfxLoadMat3(const PfxMatrix3& m) { return m; }

#endif

}  // namespace pfx
