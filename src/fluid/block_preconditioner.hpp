// SIMPLE-type block preconditioner for the assembled fluid Jacobian J = [A G; B C] (velocity A,
// pressure gradient G, divergence B, PSPG pressure block C; 4 interleaved unknowns per node):
//   u* = A~^-1 r_u,  p = S~^-1 (r_p - B u*),  u = u* - D^-1 G p,
// with D = diag(A) (SIMPLE) or the absolute row sums of A (SIMPLEC, Van Doormaal & Raithby 1984),
// S = C - B D^-1 G assembled explicitly, and A~^-1, S~^-1 one BoomerAMG V-cycle
// each (systems AMG with 3 functions on A). Constrained dofs (identity rows and columns after
// elimination) stay identity in both blocks.
#pragma once

#include "kernels/core/csr.hpp"
#include "solvers/solvers.hpp"

namespace biofsi {

class SimplePreconditioner : public AssembledPreconditioner {
 public:
  explicit SimplePreconditioner(bool row_sum = false, double strong_threshold = 0.25);
  void setup(const CsrMatrix& jacobian) override;
  void apply(ConstVector r, Vector z) const override;
  int velocity_levels() const { return amg_a_.levels(); }
  int pressure_levels() const { return amg_s_.levels(); }

 private:
  CsrMatrix a_, g_, b_, s_;
  bool row_sum_ = false;
  Vector dinv_;
  BoomerAmg amg_a_, amg_s_;
  Vector ru_, rp_, zu_, zp_, tu_, tp_;
};

}  // namespace biofsi
