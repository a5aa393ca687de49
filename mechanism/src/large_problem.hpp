#pragma once
// Large identification problems (issue 12: `mire identify` linear in the pose count,
// doc/mechanisms.md "Identify linear in the pose count"). Above kLargeProblemRows residual
// rows (5 000 H4 poses) the stacked N×P Jacobians no longer fit in the caches, and every
// dense pass over them (Householder QR, SVD preconditioning, copies) costs more per row than
// at 10⁴ rows. Such problems are reduced to P×P first: the same singular values, V and
// column norms (RᵀR = AᵀA), so the results are the same up to rounding. Smaller problems
// (every demo and test) keep the direct decompositions, bit for bit.
#include <Eigen/Core>
#include <Eigen/QR>

#include <algorithm>

namespace mire::mechanism::detail {

constexpr Eigen::Index kLargeProblemRows = 20000;

// R (at most P×P, upper triangular) with RᵀR = AᵀA: Householder QR of row blocks stacked
// under the running R (tall-skinny QR), one pass over A in cache-sized blocks.
inline Eigen::MatrixXd compressRows(const Eigen::MatrixXd& A) {
  const Eigen::Index n = A.cols();
  constexpr Eigen::Index kBlock = 2048;
  Eigen::MatrixXd stack(kBlock + n, n);
  Eigen::Index kept = 0;  // rows of the running R at the top of `stack`
  for (Eigen::Index start = 0; start < A.rows(); start += kBlock) {
    const Eigen::Index rows = std::min(kBlock, A.rows() - start);
    stack.middleRows(kept, rows) = A.middleRows(start, rows);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(stack.topRows(kept + rows));
    kept = std::min(n, kept + rows);
    stack.topRows(kept) = qr.matrixQR().topRows(kept).triangularView<Eigen::Upper>();
  }
  return stack.topRows(kept);
}

}  // namespace mire::mechanism::detail
