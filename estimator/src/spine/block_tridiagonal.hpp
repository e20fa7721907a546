#pragma once
// A symmetric block-tridiagonal system of 6×6 blocks (one block row per
// vertebra: the chain couples each vertebra only to its neighbours), solved
// by block Thomas elimination in O(n).
#include <array>
#include <cstddef>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace spinewatch::detail {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

template <std::size_t N>
struct BlockTridiagonal {
  std::array<Matrix6d, N> diag;       // A(i, i)
  std::array<Matrix6d, N - 1> upper;  // A(i, i + 1); A(i + 1, i) is its transpose
  std::array<Vector6d, N> rhs;

  void clear() {
    for (auto& d : diag) d.setZero();
    for (auto& u : upper) u.setZero();
    for (auto& r : rhs) r.setZero();
  }

  // Fixes unknown `dof` of block `i` to `value` (a Dirichlet condition),
  // keeping the matrix symmetric.
  void fix(std::size_t i, int dof, double value) {
    for (int r = 0; r < 6; ++r) rhs[i][r] -= diag[i](r, dof) * value;
    if (i > 0)
      for (int r = 0; r < 6; ++r) rhs[i - 1][r] -= upper[i - 1](r, dof) * value;
    if (i + 1 < N)
      for (int r = 0; r < 6; ++r) rhs[i + 1][r] -= upper[i](dof, r) * value;
    diag[i].row(dof).setZero();
    diag[i].col(dof).setZero();
    diag[i](dof, dof) = 1.0;
    rhs[i][dof] = value;
    if (i > 0) upper[i - 1].col(dof).setZero();
    if (i + 1 < N) upper[i].row(dof).setZero();
  }

  // Solves in place of nothing; returns x. The matrix must be positive definite.
  std::array<Vector6d, N> solve() const {
    std::array<Matrix6d, N> c;  // modified upper blocks
    std::array<Vector6d, N> d;
    Eigen::LLT<Matrix6d> llt(diag[0]);
    if (N > 1) c[0] = llt.solve(upper[0]);
    d[0] = llt.solve(rhs[0]);
    for (std::size_t i = 1; i < N; ++i) {
      const Matrix6d s = diag[i] - upper[i - 1].transpose() * c[i - 1];
      llt.compute(s);
      if (i + 1 < N) c[i] = llt.solve(upper[i]);
      d[i] = llt.solve(rhs[i] - upper[i - 1].transpose() * d[i - 1]);
    }
    std::array<Vector6d, N> x;
    x[N - 1] = d[N - 1];
    for (std::size_t i = N - 1; i-- > 0;) x[i] = d[i] - c[i] * x[i + 1];
    return x;
  }
};

}  // namespace spinewatch::detail
