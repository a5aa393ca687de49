#pragma once
// Large identification problems (`mire identify` linear in the pose count,
// doc/studies/2026-11-24-identify-scaling.md). Above kLargeProblemRows residual
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

// R (at most P×P, upper triangular) with RᵀR = AᵀA of the rows added so far: Householder QR
// of row blocks stacked under the running R (tall-skinny QR), one pass in cache-sized blocks.
// Rows may come a few at a time (one pose's residuals): they are buffered into the same
// kBlock-row blocks as a whole matrix would be, so streaming and compressRows(A) agree bit
// for bit.
class RowCompressor {
 public:
  static constexpr Eigen::Index kBlock = 2048;
  explicit RowCompressor(Eigen::Index cols) : stack_(kBlock + cols, cols) {}

  template <class Rows>
  void add(const Eigen::MatrixBase<Rows>& rows) {
    for (Eigen::Index done = 0; done < rows.rows();) {
      const Eigen::Index take = std::min(kBlock - pending_, rows.rows() - done);
      stack_.middleRows(kept_ + pending_, take) = rows.middleRows(done, take);
      pending_ += take;
      done += take;
      if (pending_ == kBlock) compress();
    }
  }

  // R of every row added (at most cols × cols).
  Eigen::MatrixXd result() {
    if (pending_ > 0) compress();
    return stack_.topRows(kept_);
  }

 private:
  void compress() {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(stack_.topRows(kept_ + pending_));
    kept_ = std::min(stack_.cols(), kept_ + pending_);
    pending_ = 0;
    stack_.topRows(kept_) = qr.matrixQR().topRows(kept_).triangularView<Eigen::Upper>();
  }

  Eigen::MatrixXd stack_;
  Eigen::Index kept_ = 0;     // rows of the running R at the top of `stack_`
  Eigen::Index pending_ = 0;  // rows added below it since the last compression
};

inline Eigen::MatrixXd compressRows(const Eigen::MatrixXd& A) {
  RowCompressor compressor(A.cols());
  compressor.add(A);
  return compressor.result();
}

}  // namespace mire::mechanism::detail
