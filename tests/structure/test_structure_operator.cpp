// Verification of the structure operator (kernels/structure through kernels/core's element loop,
// as StructureField binds it) on a distorted two-block mesh at large strain, for each material and
// for a mixed mesh: the matrix-free tangent against central finite differences of the residual, the
// matrix-free apply and diagonal against the assembled matrix, and the symmetry of that matrix;
// the mixed mesh also with the volumetric terms at the element centre (a second element loop).
// The state is a dynamic one-step-theta step (theta 0.66), so every term of the residual is live:
// inertia with the old velocity, theta P(F_{n+1}) + (1 - theta) P(F_n), nodal body force, gravity
// and a dead-load traction; a clamped face makes constrained rows.
//
// Tolerances, and why:
//  * Finite differences: central, along a direction that leaves the constrained dofs alone (the
//    tangent eliminates their columns). Truncation is h^2 |r'''| / 6 and round-off ~eps |r| / h:
//    at h = 1e-6 both are ~1e-11 relative, so 1e-7 relative to |J du| leaves four decades, while a
//    missing or wrong tangent term (geometric stiffness, Neo-Hooke's volumetric part, theta, the
//    mass term) is an O(1e-2..1) relative error at these strains (Green-Lagrange up to ~0.3). So
//    that a tangent with a small error of its own cannot pass by luck, the error at h = 1e-3 must
//    exceed the one at h = 1e-6 a hundredfold: the O(h^2) truncation is visible, and a tangent
//    error would be a floor common to both.
//  * 1e-12 relative (to the largest entry) for matrix-free apply and diagonal against the assembled
//    matrix: the same operator in another summation order (sum factorisation versus element
//    columns), so they agree to round-off (~1e-15); any difference in the physics is O(1).
//  * 1e-12 for symmetry: hyperelasticity with dead loads has a symmetric tangent (second
//    derivative of an energy); the theta-weighted old stress is constant and does not enter it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "kernels/core/csr.hpp"
#include "structure/structure_test_support.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

Mesh operator_mesh() {
  Mesh m = box_mesh(3, 3, 1.0, {{"lower", 0.0, 0.4, 2, 1.0}, {"upper", 0.4, 1.0, 3, 2.0}});
  distort(m, [](const Point& p) { return smooth_cube_map(p, 0.06); });
  return m;
}

// Smooth, sign-changing fields with different components; `a` sets the size of the gradients.
std::vector<Point> wiggly(const Mesh& m, double a, double phase) {
  std::vector<Point> v(m.n_nodes());
  for (int n = 0; n < m.n_nodes(); ++n) {
    const double x = m.x[n][0], y = m.x[n][1], z = m.x[n][2];
    v[n] = {a * std::sin(2.1 * x - 1.3 * y + 0.7 * z + phase) * std::cos(0.9 * x + 1.7 * y),
            a * (0.5 + std::cos(1.4 * x + 0.6 * y - 1.9 * z + phase)),
            a * (x * y - 0.8 * std::sin(1.1 * y + 2.3 * z + phase))};
  }
  return v;
}

HostVector flat(const std::vector<Point>& v) {
  HostVector out(3 * v.size());
  for (size_t n = 0; n < v.size(); ++n)
    for (int c = 0; c < 3; ++c) out[3 * n + c] = v[n][c];
  return out;
}

struct Case {
  std::string name;
  StructureModel lower, upper;
  VolumetricIntegration volumetric = VolumetricIntegration::Full;
};

const Case cases[] = {
    {"St.Venant-Kirchhoff", SaintVenantKirchhoff, SaintVenantKirchhoff},
    {"Neo-Hooke", NeoHooke, NeoHooke},
    {"mixed", SaintVenantKirchhoff, NeoHooke},
    {"mixed, reduced volumetric", SaintVenantKirchhoff, NeoHooke, VolumetricIntegration::Reduced}};

std::unique_ptr<StructureField> make_field(const Mesh& mesh, const Case& c) {
  StructureMaterial lower = material(c.lower, 2.0, 0.3, 1.5);
  StructureMaterial upper = material(c.upper, 0.7, 0.45, 0.8);
  lower.gravity = {0.1, -1.0, 0.2};
  upper.gravity = {0.0, -1.0, 0.0};
  StructureSettings s = tight_structure_settings({lower, upper}, false);
  s.theta = 0.66;
  s.volumetric_integration = c.volumetric;
  StructureTraction t{
      "right",
      {constant(0.05), [](const Point& x, double) { return 0.1 * x[1]; }, constant(-0.02)}};
  auto f = std::make_unique<StructureField>(mesh, s, std::vector<StructureDirichlet>{clamp("left")},
                                            std::vector<StructureTraction>{t});
  f->set_body_force({[](const Point& x, double) { return std::sin(x[1]); }, constant(0.3),
                     [](const Point& x, double) { return x[0] * x[2]; }});
  // d_n with strains ~0.3, a velocity, and a step of moderate size.
  f->set_state(wiggly(mesh, 0.25, 0.0), wiggly(mesh, 0.8, 1.0), 0.0);
  f->prepare_step(0.05);
  return f;
}

std::vector<int> to_host_indices(ConstIndexView v) {
  auto h = Kokkos::create_mirror_view_and_copy(HostSpace(), v);
  return std::vector<int>(h.data(), h.data() + h.extent(0));
}

HostVector residual_at(const StructureField& f, const HostVector& u) {
  Vector r(std::string("test::r"), u.size());
  f.residual(to_device(u), r);
  return to_host(r);
}

HostVector tangent_at(const StructureField& f, const HostVector& u, const HostVector& du) {
  Vector y(std::string("test::y"), u.size());
  f.apply_tangent(to_device(u), to_device(du), y);
  return to_host(y);
}

double fd_error(const StructureField& f, const HostVector& u, const HostVector& du, double h) {
  HostVector up(u), um(u);
  for (size_t i = 0; i < u.size(); ++i) up[i] += h * du[i], um[i] -= h * du[i];
  const HostVector rp = residual_at(f, up), rm = residual_at(f, um);
  const HostVector jdu = tangent_at(f, u, du);
  HostVector fd(u.size());
  for (size_t i = 0; i < u.size(); ++i) fd[i] = (rp[i] - rm[i]) / (2 * h);
  return norm([&] {
           HostVector d(u.size());
           for (size_t i = 0; i < u.size(); ++i) d[i] = fd[i] - jdu[i];
           return d;
         }()) /
         norm(jdu);
}

}  // namespace

TEST(StructureOperator, TangentMatchesFiniteDifferencesAtLargeStrain) {
  const Mesh mesh = operator_mesh();
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    auto f = make_field(mesh, c);
    const HostVector u = flat(wiggly(mesh, 0.1, 2.0));
    // The tangent eliminates constrained columns (their increments are fixed), so the directions
    // compared leave them alone.
    HostVector du = flat(wiggly(mesh, 1.0, 3.0));
    for (int dof : to_host_indices(f->constrained_dofs())) du[dof] = 0;
    const double coarse = fd_error(*f, u, du, 1e-3);
    const double fine = fd_error(*f, u, du, 1e-6);
    std::printf("[ measured ] %s: |FD - J du|/|J du| = %.2e (h = 1e-3), %.2e (h = 1e-6)\n",
                c.name.c_str(), coarse, fine);
    EXPECT_LT(fine, 1e-7);
    // Truncation O(h^2) must be visible at the large step (the residual is genuinely nonlinear
    // here) and shrink by orders of magnitude: a tangent with an error of its own would not.
    EXPECT_GT(coarse, 100 * fine);
  }
}

TEST(StructureOperator, ApplyAndDiagonalEqualAssembledMatrix) {
  const Mesh mesh = operator_mesh();
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    auto f = make_field(mesh, c);
    const HostVector u = flat(wiggly(mesh, 0.1, 2.0));
    const HostVector du = flat(wiggly(mesh, 1.0, 3.0));
    const Vector ud = to_device(u);
    f->assemble(ud, true);
    const CsrMatrix& a = f->matrix();
    Vector y(std::string("test::y"), u.size());
    csr_multiply(a, to_device(du), y);
    const HostVector au = to_host(y);
    const HostVector ku = tangent_at(*f, u, du);
    Vector ys(std::string("test::ys"), u.size());
    f->linearise(ud);
    f->apply_linearised(to_device(du), ys);
    const double stored = max_abs_difference(to_host(ys), au) / max_abs(au);
    Vector dd(std::string("test::d"), u.size()), da(std::string("test::da"), u.size());
    f->diagonal(ud, dd);
    csr_diagonal(a, da);
    const HostVector d_mf = to_host(dd), d_a = to_host(da);
    const double apply = max_abs_difference(ku, au) / max_abs(au);
    const double diag = max_abs_difference(d_mf, d_a) / max_abs(d_a);
    // Symmetry of the assembled, constraint-eliminated tangent.
    auto rp = Kokkos::create_mirror_view_and_copy(HostSpace(), a.row_ptr);
    auto col = Kokkos::create_mirror_view_and_copy(HostSpace(), a.col);
    const HostVector val = to_host(a.val);
    double asym = 0;
    for (int r = 0; r < a.n_rows; ++r)
      for (int k = rp(r); k < rp(r + 1); ++k) {
        const int cc = col(k);
        for (int kt = rp(cc); kt < rp(cc + 1); ++kt)
          if (col(kt) == r) asym = std::max(asym, std::abs(val[k] - val[kt]));
      }
    asym /= max_abs(val);
    std::printf(
        "[ measured ] %s: apply vs CSR %.2e, stored tangent vs CSR %.2e, diagonal vs CSR %.2e, "
        "asymmetry %.2e\n",
        c.name.c_str(), apply, stored, diag, asym);
    EXPECT_LT(apply, 1e-12);
    EXPECT_LT(stored, 1e-12);
    EXPECT_LT(diag, 1e-12);
    EXPECT_LT(asym, 1e-12);
  }
}
