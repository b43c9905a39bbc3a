// The numeric core shared by the direct solvers over trees of bodies and constraints
// (joints in pfx_joint_tree_solver, contacts in pfx_contact_tree_solver), after Baraff,
// "Linear-Time Dynamics using Lagrange Multipliers" (SIGGRAPH 1996). Every node is a body
// (6 velocity unknowns) or a constraint (up to 6 rows, padded with rows that couple to
// nothing); the system [M J^T; J -C] then has the sparsity of the tree, and eliminating
// leaves first factors it with no fill-in, in time linear in the number of nodes.
#pragma once

#include <Eigen/LU>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "pfx/base_level/solver/pfx_solver_body.h"

namespace pfx {

// Factoring in double keeps mass ratios of 1:1000 and more well inside the precision.
using PfxTreeBlock = Eigen::Matrix<double, 6, 6>;
using PfxTreeVector = Eigen::Matrix<double, 6, 1>;

struct PfxBlockTreeNode {
  PfxTreeBlock diagonalInverse;  // holds D until factored, then D^-1 after elimination
  PfxTreeBlock toParent;         // holds H(node, parent) until factored, then L = D^-1 H
  PfxTreeVector value;           // right-hand side, then solution
  PfxInt32 parent;               // node index, -1 at a root
};

// The mass matrix of a body node.
inline PfxTreeBlock pfxTreeBodyMass(const PfxSolverBody& body) {
  PfxTreeBlock mass = PfxTreeBlock::Zero();
  mass.topLeftCorner<3, 3>().diagonal().setConstant(1.0 / double(body.m_massInv));
  mass.bottomRightCorner<3, 3>() = body.m_inertiaInv.cast<double>().inverse();
  return mass;
}

// The inverse of that mass matrix, from the body's inverse mass and inertia as they are: the
// pivot of a body eliminated before anything was eliminated into it (a leaf), which then
// needs no inversion. Symmetric, from the lower triangle, as an inverted pivot is.
inline PfxTreeBlock pfxTreeBodyMassInverse(const PfxSolverBody& body) {
  PfxTreeBlock inverse = PfxTreeBlock::Zero();
  inverse.topLeftCorner<3, 3>().diagonal().setConstant(double(body.m_massInv));
  for (int j = 0; j < 3; ++j) {
    for (int i = j; i < 3; ++i) {
      inverse(3 + i, 3 + j) = inverse(3 + j, 3 + i) = double(body.m_inertiaInv(i, j));
    }
  }
  return inverse;
}

namespace block_tree_detail {

// The top left N x N of a definite block (columns 6 apart), inverted in place by the
// LDL^T that pfxInvertDefiniteBlock describes; reads the lower triangle. Every loop is
// unrolled: the inner loops' bounds follow the outer ones', so the compiler left them as
// loops, and a 6 x 6 inverse cost 1,510 instructions instead of 530 (a third of the
// factorization of the robots' trees).
template <int N>
void invertDefinite(double* a) {
  if constexpr (N > 0) {
    double l[N][N];   // unit lower triangular factor, below the diagonal
    double ld[N][N];  // l times the pivot of its column
    double inversePivot[N];
    #pragma GCC unroll 6
    for (int j = 0; j < N; ++j) {
      double dj = a[j + 6 * j];
      #pragma GCC unroll 6
      for (int k = 0; k < j; ++k) dj -= l[j][k] * ld[j][k];
      inversePivot[j] = 1.0 / dj;
      #pragma GCC unroll 6
      for (int i = j + 1; i < N; ++i) {
        double lij = a[i + 6 * j];
        #pragma GCC unroll 6
        for (int k = 0; k < j; ++k) lij -= l[i][k] * ld[j][k];
        ld[i][j] = lij;
        l[i][j] = lij * inversePivot[j];
      }
    }
    // x = L^-1, unit lower triangular.
    double x[N][N];
    #pragma GCC unroll 6
    for (int i = 0; i < N; ++i) {
      #pragma GCC unroll 6
      for (int j = 0; j < i; ++j) {
        double sum = l[i][j];
        #pragma GCC unroll 6
        for (int k = j + 1; k < i; ++k) sum += l[i][k] * x[k][j];
        x[i][j] = -sum;
      }
    }
    // A^-1 = L^-T D^-1 L^-1, symmetric.
    #pragma GCC unroll 6
    for (int j = 0; j < N; ++j) {
      #pragma GCC unroll 6
      for (int i = j; i < N; ++i) {
        double sum = (i == j ? 1.0 : x[i][j]) * inversePivot[i];
        #pragma GCC unroll 6
        for (int k = i + 1; k < N; ++k) sum += x[k][i] * x[k][j] * inversePivot[k];
        a[i + 6 * j] = sum;
        a[j + 6 * i] = sum;
      }
    }
  }
}

}  // namespace block_tree_detail

// The inverse of a pivot of the elimination below, from its lower triangle. Every pivot is
// definite, so an LDL^T factorization needs no pivoting: a body's pivot is its mass plus
// what its eliminated constraints add (positive definite), a constraint's is its
// compliance minus what its eliminated bodies answer (negative definite). Written out for
// 6 x 6, it costs a fraction of Eigen's general inverse of a fixed 6 x 6 block, a partially
// pivoted LU through the dynamic-size kernels, which was a third of a robot arm's step.
inline PfxTreeBlock pfxInvertDefiniteBlock(const PfxTreeBlock& a) {
  PfxTreeBlock inverse = a;
  block_tree_detail::invertDefinite<6>(inverse.data());
  return inverse;
}

// Nodes numbered breadth first, parents before children: eliminating in reverse order
// takes children first, D_parent -= H(p, n) D_n^-1 H(n, p). Each tree of the forest is a
// contiguous range [begin, end) of nodes whose parents lie in it, so trees factor and
// solve independently. The pivots are symmetric and only their lower triangles are read,
// so the update computes that half.
template <typename Node>
void pfxFactorBlockTree(Node* nodes, std::size_t begin, std::size_t end) {
  for (std::size_t k = end; k-- > begin;) {
    Node& node = nodes[k];
    node.diagonalInverse = pfxInvertDefiniteBlock(node.diagonalInverse);
    if (node.parent < 0) continue;
    // H is needed only here, so it lives in toParent until L replaces it: a node of
    // three blocks instead of four (a contact tree holds two nodes per resting body).
    const PfxTreeBlock coupling = node.toParent;
    node.toParent.noalias() = node.diagonalInverse * coupling;
    PfxTreeBlock& parentPivot = nodes[node.parent].diagonalInverse;
    for (int j = 0; j < 6; ++j) {
      for (int i = j; i < 6; ++i) parentPivot(i, j) -= coupling.col(i).dot(node.toParent.col(j));
    }
  }
}

// Solves the factored system for the right-hand sides in `value`, in place: forward
// (children first), diagonal, then backward (parents first). Nodes [begin, end) must be
// whole trees: every parent of a node in the range lies in it too.
template <typename Node>
void pfxSolveBlockTree(Node* nodes, std::size_t begin, std::size_t end) {
  for (std::size_t k = end; k-- > begin;) {
    const Node& node = nodes[k];
    if (node.parent >= 0) nodes[node.parent].value -= node.toParent.transpose() * node.value;
  }
  for (std::size_t n = begin; n < end; ++n) {
    nodes[n].value = (nodes[n].diagonalInverse * nodes[n].value).eval();
  }
  for (std::size_t k = begin; k < end; ++k) {
    Node& node = nodes[k];
    if (node.parent >= 0) node.value -= node.toParent * nodes[node.parent].value;
  }
}

// The same elimination for trees whose nodes have fewer unknowns than 6: a node reports
// its count with blockSize() (a body 6, a joint its locked rows), uses the top left
// blockSize() x blockSize() of its pivot, and its coupling to its parent is the top left
// blockSize() x parent's blockSize() of toParent; the rest of each block is never read or
// written. A ball joint's three rows then cost a 3 x 3 pivot instead of a 6 x 6 one padded
// with rows that couple to nothing, and the kernels below are unrolled for each pair of
// sizes, where Eigen's 6 x 6 products were a tenth of a robot arm's step.
namespace block_tree_detail {

template <int N>
using Size = std::integral_constant<int, N>;

// Calls f(Size<n>{}) for n in [0, 6].
template <typename F>
void withSize(int n, F&& f) {
  switch (n) {
    case 0: f(Size<0>{}); break;
    case 1: f(Size<1>{}); break;
    case 2: f(Size<2>{}); break;
    case 3: f(Size<3>{}); break;
    case 4: f(Size<4>{}); break;
    case 5: f(Size<5>{}); break;
    default: f(Size<6>{}); break;
  }
}

// Eliminates an N-unknown child into its P-unknown parent: L = D^-1 H, then
// D_parent -= H^T L on the parent's lower triangle.
template <int N, int P>
void eliminate(double* dInverse, double* toParent, double* parentPivot) {
  double h[N * P > 0 ? N * P : 1];
  for (int j = 0; j < P; ++j) {
    for (int i = 0; i < N; ++i) h[i + N * j] = toParent[i + 6 * j];
  }
  for (int j = 0; j < P; ++j) {
    double sum[N > 0 ? N : 1] = {};
    for (int k = 0; k < N; ++k) {
      for (int i = 0; i < N; ++i) sum[i] += dInverse[i + 6 * k] * h[k + N * j];
    }
    for (int i = 0; i < N; ++i) toParent[i + 6 * j] = sum[i];
  }
  for (int j = 0; j < P; ++j) {
    for (int i = j; i < P; ++i) {
      double sum = 0;
      for (int k = 0; k < N; ++k) sum += h[k + N * i] * toParent[k + 6 * j];
      parentPivot[i + 6 * j] -= sum;
    }
  }
}

// value_parent -= L^T value_child.
template <int N, int P>
void forward(const double* toParent, const double* value, double* parentValue) {
  double sum[P > 0 ? P : 1] = {};
  for (int k = 0; k < N; ++k) {
    for (int i = 0; i < P; ++i) sum[i] += toParent[k + 6 * i] * value[k];
  }
  for (int i = 0; i < P; ++i) parentValue[i] -= sum[i];
}

// value = D^-1 value.
template <int N>
void diagonal(const double* dInverse, double* value) {
  double solved[N > 0 ? N : 1] = {};
  for (int k = 0; k < N; ++k) {
    for (int i = 0; i < N; ++i) solved[i] += dInverse[i + 6 * k] * value[k];
  }
  for (int i = 0; i < N; ++i) value[i] = solved[i];
}

// value_child -= L value_parent.
template <int N, int P>
void backward(const double* toParent, const double* parentValue, double* value) {
  double sum[N > 0 ? N : 1] = {};
  for (int k = 0; k < P; ++k) {
    for (int i = 0; i < N; ++i) sum[i] += toParent[i + 6 * k] * parentValue[k];
  }
  for (int i = 0; i < N; ++i) value[i] -= sum[i];
}

}  // namespace block_tree_detail

// A node whose pivotInverted() is true comes with D^-1 in place of D.
template <typename Node>
void pfxFactorSizedBlockTree(Node* nodes, std::size_t begin, std::size_t end) {
  using namespace block_tree_detail;
  for (std::size_t k = end; k-- > begin;) {
    Node& node = nodes[k];
    withSize(node.blockSize(), [&](auto n) {
      constexpr int N = decltype(n)::value;
      if (!node.pivotInverted()) invertDefinite<N>(node.diagonalInverse.data());
      if (node.parent < 0) return;
      Node& parent = nodes[node.parent];
      withSize(parent.blockSize(), [&](auto p) {
        eliminate<N, decltype(p)::value>(node.diagonalInverse.data(), node.toParent.data(),
                                         parent.diagonalInverse.data());
      });
    });
  }
}

// Forward, diagonal and backward steps of one node, for solves over a whole tree
// (pfxSolveSizedBlockTree) or along one path of it.
template <typename Node>
void pfxSizedBlockTreeForward(const Node& node, Node& parent) {
  using namespace block_tree_detail;
  withSize(node.blockSize(), [&](auto n) {
    withSize(parent.blockSize(), [&](auto p) {
      forward<decltype(n)::value, decltype(p)::value>(node.toParent.data(), node.value.data(),
                                                      parent.value.data());
    });
  });
}

template <typename Node>
void pfxSizedBlockTreeDiagonal(Node& node) {
  using namespace block_tree_detail;
  withSize(node.blockSize(), [&](auto n) {
    diagonal<decltype(n)::value>(node.diagonalInverse.data(), node.value.data());
  });
}

template <typename Node>
void pfxSizedBlockTreeBackward(Node& node, const Node& parent) {
  using namespace block_tree_detail;
  withSize(node.blockSize(), [&](auto n) {
    withSize(parent.blockSize(), [&](auto p) {
      backward<decltype(n)::value, decltype(p)::value>(node.toParent.data(), parent.value.data(),
                                                       node.value.data());
    });
  });
}

// `mayBeNonZero(n)` is false only for nodes whose right-hand side and descendants' are
// all zero: their forward and diagonal steps, which would add and leave zeros, are
// skipped (a unit impulse at one joint of an arm loads only its path to the root).
template <typename Node, typename NodePredicate>
void pfxSolveSizedBlockTree(Node* nodes, std::size_t begin, std::size_t end,
                            NodePredicate mayBeNonZero) {
  for (std::size_t k = end; k-- > begin;) {
    if (nodes[k].parent >= 0 && mayBeNonZero(k)) {
      pfxSizedBlockTreeForward(nodes[k], nodes[nodes[k].parent]);
    }
  }
  for (std::size_t n = begin; n < end; ++n) {
    if (mayBeNonZero(n)) pfxSizedBlockTreeDiagonal(nodes[n]);
  }
  for (std::size_t k = begin; k < end; ++k) {
    if (nodes[k].parent >= 0) pfxSizedBlockTreeBackward(nodes[k], nodes[nodes[k].parent]);
  }
}

template <typename Node>
void pfxSolveSizedBlockTree(Node* nodes, std::size_t begin, std::size_t end) {
  pfxSolveSizedBlockTree(nodes, begin, end, [](std::size_t) { return true; });
}

// Union-find root with path halving, for picking the constraints that form a forest.
inline PfxInt32 pfxFindTreeRoot(PfxInt32* parent, PfxInt32 i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

// Carves aligned arrays out of the caller's work buffer.
class PfxWorkCarver {
 public:
  PfxWorkCarver(void* buffer, std::size_t bytes)
      : m_cursor(static_cast<unsigned char*>(buffer)), m_end(m_cursor + bytes) {}
  template <typename T>
  T* take(std::size_t count) {
    unsigned char* begin = alignedCursor<T>();
    if (begin + count * sizeof(T) > m_end) return nullptr;
    m_cursor = begin + count * sizeof(T);
    return reinterpret_cast<T*>(begin);
  }
  // What is left, as whole Ts; count receives how many.
  template <typename T>
  T* takeRest(std::size_t& count) {
    unsigned char* begin = alignedCursor<T>();
    count = begin < m_end ? std::size_t(m_end - begin) / sizeof(T) : 0;
    m_cursor = begin + count * sizeof(T);
    return reinterpret_cast<T*>(begin);
  }
  static std::size_t bytesFor(std::size_t alignment, std::size_t bytes) {
    return bytes + alignment;
  }

 private:
  template <typename T>
  unsigned char* alignedCursor() const {
    const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(m_cursor);
    return reinterpret_cast<unsigned char*>((at + alignof(T) - 1) &
                                            ~(std::uintptr_t(alignof(T)) - 1));
  }

  unsigned char* m_cursor;
  unsigned char* m_end;
};

}  // namespace pfx
