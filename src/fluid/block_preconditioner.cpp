#include "fluid/block_preconditioner.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace biofsi {

namespace {

AmgOptions velocity_amg(double strong_threshold) {
  AmgOptions o;
  o.num_functions = 3;
  o.nodal_coarsening = true;
  o.strong_threshold = strong_threshold;
  return o;
}

struct HostCsr {
  int n_rows = 0;
  std::vector<int> row_ptr{0}, col;
  std::vector<double> val;
  void end_row() { row_ptr.push_back(static_cast<int>(col.size())); }
};

CsrMatrix to_device(const HostCsr& h, const std::string& label) {
  CsrMatrix m;
  m.n_rows = static_cast<int>(h.row_ptr.size()) - 1;
  m.row_ptr = Kokkos::View<int*, MemSpace>(label + "::row_ptr", h.row_ptr.size());
  m.col = Kokkos::View<int*, MemSpace>(label + "::col", h.col.size());
  m.val = Kokkos::View<Real*, MemSpace>(label + "::val", h.val.size());
  auto rp = Kokkos::create_mirror_view(m.row_ptr);
  auto c = Kokkos::create_mirror_view(m.col);
  auto v = Kokkos::create_mirror_view(m.val);
  for (size_t i = 0; i < h.row_ptr.size(); ++i) rp(i) = h.row_ptr[i];
  for (size_t i = 0; i < h.col.size(); ++i) {
    c(i) = h.col[i];
    v(i) = h.val[i];
  }
  Kokkos::deep_copy(m.row_ptr, rp);
  Kokkos::deep_copy(m.col, c);
  Kokkos::deep_copy(m.val, v);
  return m;
}

// The four blocks of a Jacobian with 4 interleaved unknowns per node, and diag(A) (or, row_sum, the
// absolute row sums of A with the diagonal's sign) inverted.
struct SplitJacobian {
  HostCsr a, g, b, c;
  std::vector<double> dinv;
};

SplitJacobian split_jacobian(const CsrMatrix& j, bool row_sum) {
  if (j.n_rows % 4 != 0)
    throw std::invalid_argument("fluid preconditioner: rows are not 4 per node");
  const int nn = j.n_rows / 4;
  auto rp = Kokkos::create_mirror_view_and_copy(HostSpace(), j.row_ptr);
  auto col = Kokkos::create_mirror_view_and_copy(HostSpace(), j.col);
  auto val = Kokkos::create_mirror_view_and_copy(HostSpace(), j.val);
  SplitJacobian out;
  HostCsr &a = out.a, &g = out.g, &b = out.b, &c = out.c;
  out.dinv.assign(3 * nn, 1.0);
  for (int r = 0; r < j.n_rows; ++r) {
    const int comp = r % 4;
    double diag = 0, abs_sum = 0;
    for (int k = rp(r); k < rp(r + 1); ++k) {
      const int m = col(k) / 4, d = col(k) % 4;
      HostCsr& target = comp < 3 ? (d < 3 ? a : g) : (d < 3 ? b : c);
      target.col.push_back(d < 3 ? 3 * m + d : m);
      target.val.push_back(val(k));
      if (col(k) == r) diag = val(k);
      if (d < 3) abs_sum += std::abs(val(k));
    }
    if (comp < 3) {
      // SIMPLEC keeps the sign of the diagonal (positive here: mass, viscosity, SUPG).
      const double dd = row_sum ? (diag < 0 ? -abs_sum : abs_sum) : diag;
      out.dinv[3 * (r / 4) + comp] = dd != 0 ? 1 / dd : 1.0;
    }
    if (comp < 3) {
      a.end_row();
      g.end_row();
    } else {
      b.end_row();
      c.end_row();
    }
  }
  return out;
}

}  // namespace

SimplePreconditioner::SimplePreconditioner(bool row_sum, double strong_threshold)
    : row_sum_(row_sum), amg_a_(velocity_amg(strong_threshold)), amg_s_(AmgOptions{}) {}

void SimplePreconditioner::setup(const CsrMatrix& j) {
  const int nn = j.n_rows / 4;
  SplitJacobian split = split_jacobian(j, row_sum_);
  const HostCsr &a = split.a, &g = split.g, &b = split.b, &c = split.c;
  const std::vector<double>& dinv = split.dinv;
  // S = C - B D^-1 G, row by row with a dense accumulator (classical sparse product).
  HostCsr s;
  std::vector<double> acc(nn, 0.0);
  std::vector<int> marker(nn, -1), cols;
  for (int i = 0; i < nn; ++i) {
    cols.clear();
    auto add = [&](int k, double v) {
      if (marker[k] != i) {
        marker[k] = i;
        acc[k] = 0;
        cols.push_back(k);
      }
      acc[k] += v;
    };
    for (int k = c.row_ptr[i]; k < c.row_ptr[i + 1]; ++k) add(c.col[k], c.val[k]);
    for (int k = b.row_ptr[i]; k < b.row_ptr[i + 1]; ++k) {
      const int u = b.col[k];
      const double w = b.val[k] * dinv[u];
      if (w == 0) continue;
      for (int l = g.row_ptr[u]; l < g.row_ptr[u + 1]; ++l) add(g.col[l], -w * g.val[l]);
    }
    std::sort(cols.begin(), cols.end());
    for (int k : cols) {
      s.col.push_back(k);
      s.val.push_back(acc[k]);
    }
    s.end_row();
  }
  a_ = to_device(a, "biofsi::simple_a");
  g_ = to_device(g, "biofsi::simple_g");
  b_ = to_device(b, "biofsi::simple_b");
  s_ = to_device(s, "biofsi::simple_s");
  dinv_ = Vector("biofsi::simple_dinv", 3 * nn);
  auto dh = Kokkos::create_mirror_view(dinv_);
  for (int i = 0; i < 3 * nn; ++i) dh(i) = dinv[i];
  Kokkos::deep_copy(dinv_, dh);
  ru_ = Vector("biofsi::simple_ru", 3 * nn);
  zu_ = Vector("biofsi::simple_zu", 3 * nn);
  tu_ = Vector("biofsi::simple_tu", 3 * nn);
  rp_ = Vector("biofsi::simple_rp", nn);
  zp_ = Vector("biofsi::simple_zp", nn);
  tp_ = Vector("biofsi::simple_tp", nn);
  amg_a_.setup(a_);
  amg_s_.setup(s_);
}

void SimplePreconditioner::apply(ConstVector r, Vector z) const {
  const int nn = static_cast<int>(rp_.extent(0));
  auto ru = ru_, zu = zu_, tu = tu_, rp = rp_, zp = zp_, tp = tp_;
  auto dinv = dinv_;
  Kokkos::parallel_for(
      "biofsi::simple_split", Kokkos::RangePolicy<ExecSpace>(0, nn), KOKKOS_LAMBDA(int n) {
        for (int d = 0; d < 3; ++d) ru(3 * n + d) = r(4 * n + d);
        rp(n) = r(4 * n + 3);
      });
  amg_a_.apply(ru, zu);
  csr_multiply(b_, zu, tp);
  Kokkos::parallel_for(
      "biofsi::simple_schur_rhs", Kokkos::RangePolicy<ExecSpace>(0, nn),
      KOKKOS_LAMBDA(int n) { tp(n) = rp(n) - tp(n); });
  amg_s_.apply(tp, zp);
  csr_multiply(g_, zp, tu);
  Kokkos::parallel_for(
      "biofsi::simple_merge", Kokkos::RangePolicy<ExecSpace>(0, nn), KOKKOS_LAMBDA(int n) {
        for (int d = 0; d < 3; ++d) z(4 * n + d) = zu(3 * n + d) - dinv(3 * n + d) * tu(3 * n + d);
        z(4 * n + 3) = zp(n);
      });
}

}  // namespace biofsi
