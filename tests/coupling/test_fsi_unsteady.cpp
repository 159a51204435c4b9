// Turek & Hron (2006) FSI2 and FSI3: the elastic flag behind the cylinder oscillating in the flow
// it sheds (fsi_benchmarks.hpp), run from rest to a periodic state and compared with the
// benchmark's mean, amplitude and frequency of u_x(A), u_y(A), drag and lift. Label long: on the
// development machine FSI2 takes ~3 h on 2 threads (440 steps on turek_hron_wake, the refine-1
// body with a finer wake on which CFD3 passes) and FSI3 ~9 h on one thread (490 steps, 35-110 s a
// step on turek_hron_flag, that mesh with refine 2's flag).
//
// Each case runs in stages (UnsteadyCase::stages): a start-up with a large step (and for FSI2
// theta 0.52, which damps the swing but survives its growth), then the periodic state measured
// with Crank-Nicolson and a smaller step, each stage continuing from the state the last reached.
//
// Measured with the default stages from rest (docs/validation.md has the full tables):
//   FSI2 to t = 6.6 s (no cut step): u_y(A) amplitude -3.4%, lift -6.2%, drag amplitude -6.6%,
//   the rest within 5.3% (fsi2() lists everything).
//   FSI3 to t = 3.4 s (no cut step), against the benchmark authors' finest row (fsi3() gives the
//   source): u_y(A) amplitude -1.1% at -2.3% frequency, u_x(A) mean -0.7% and amplitude -3.6%,
//   drag 460.2 +- 26.9 (mean -0.06%, amplitude -3.1%), lift +-159.8 (+3.8%), all frequencies
//   within 2.3%. Against the 2006 proposal's summary row, reported beside it, the drag amplitude
//   is +18.6% and the lift +6.7%: that row's drag amplitude, 22.66, is 18% below the finer row's
//   27.74. The drag amplitude is not mesh-converged: the t = 3.4 s state moved onto the 1.5x
//   refinement of turek_hron_flag (43086 nodes) and run to t = 3.69 s (~1.3 swings after the
//   transfer) gives u_y(A) 1.42e-3 +- 3.521e-2 at 5.48 Hz, u_x(A) +-2.71e-3 and lift +-155.6, all
//   within ~1% of the finer row, but drag 426.6-491.0 (+-32.2, +16%) (docs/known-limits.md).
//
// Why FSI3 runs on turek_hron_flag: refine 1's flag is too stiff (CSM3 on it: frequency +3.6%,
// amplitude -7.9%; on refine 2's flag +0.6%, -2.4%), and with refine 2's flag the lift per unit
// swing is 11-13% lower than on turek_hron_wake, where the same stages give lift +-173 (the finer
// row: 153.91); the drag's 10.8 Hz oscillation is the same on both meshes (+-27, of which +-25 on
// the flag). An FSI3 step costs ~2.1x the wake mesh's. The lift is an interference sum: the
// flag's part leads u_y(A) by ~150 degrees (inertia-dominated, as a flag driven at 5.4 Hz, above
// its in-vacuo first mode at ~2 Hz, must be), the cylinder's by 30-45, so a 15-degree phase error
// of the shedding against the swing moves the total by ~30 N/m. The fluid alone on these meshes
// sheds 7-14% weak (tests/fluid/test_fluid_unsteady.cpp).
//
// Environment, for studies (defaults in brackets): BIOFSI_FSI_MESH [FSI2 turek_hron_wake, FSI3
// turek_hron_flag: a mesh of the build, e.g. turek_hron_r1 or turek_hron_r2, or the path of a
// .msh file of cases/meshes/turek_hron.geo made with other gmsh parameters; test_fluid_unsteady's
// CFD3 measures a candidate's wake], BIOFSI_FSI_T_END [the last stage's end: the stages are cut
// there], BIOFSI_FSI_STAGES ["dt,theta,stiffening,t_end;...": replaces the case's stages],
// BIOFSI_FSI_DT, BIOFSI_FSI_THETA (fluid and structure), BIOFSI_FSI_STIFFENING (the fluid mesh's):
// any of these three makes the run one stage with their values (the others from the case's last
// stage), BIOFSI_FSI_STEADY_TAU [0],
// BIOFSI_FSI_RAMP [0.5], BIOFSI_FSI_KICK [FSI2 4, FSI3 0: the peak of the transverse seeding pulse
// on the flag, m/s^2], BIOFSI_FSI_SIMPLE [0: the fluid block preconditioned by SIMPLEC; 1: SIMPLE],
// BIOFSI_FSI_NEWTON_TOL [FSI2 1e-6, FSI3 1e-4: each field's Newton tolerance relative to its
// largest residual in the step], BIOFSI_FSI_INNER_TOL [1e-2: the block solves' relative tolerance],
// BIOFSI_FSI_SERIES (a folder: the time series is written there as fsi<k>_series.csv after every
// step), BIOFSI_FSI_FROM_SERIES (such a file: analyse it instead of running, e.g. a run stopped
// early; pick the case with --gtest_filter), BIOFSI_FSI_CHECKPOINT (a file: the state is saved
// there every BIOFSI_FSI_CHECKPOINT_EVERY [10] steps), BIOFSI_FSI_RESTART (such a file: continue
// from it, in the stage its time falls in, with its series read back from BIOFSI_FSI_SERIES so the
// analysis covers the whole run; the step may differ from the one that wrote it),
// BIOFSI_FSI_RESTART_MESH (with BIOFSI_FSI_RESTART: the mesh the checkpoint was written on, when
// it is not this run's; its state is interpolated onto this run's mesh and a new series starts:
// a mesh study from a periodic state. The interpolated velocity is not divergence-free on the
// new mesh, which sets off Crank-Nicolson's undamped alternating mode in the drag: +-170 N/m at
// the first step from turek_hron_flag to its 1.5x refinement, decaying over some 40 steps, which
// the analysis must leave out. A first stage with theta 0.55 damps it to +-2 within 20 steps of
// 0.0025 s; one with theta 1 is no remedy: its third step takes 329 Krylov iterations (the first
// two 58 and 84; the cause is not known)),
// BIOFSI_FSI_VERBOSE [0] (1: every step's Newton history, residual norms per field).
//
// How the numbers are taken: as the benchmark does, over the last full period of each signal
// (oscillation.hpp, tested in the default suite).
//
// Neither case can pass on refine 1 (turek_hron_r1), where the fluid alone does not shed as the
// benchmark does (CFD3's lift amplitude is a third of the reference's there).
//
// The start differs from the benchmark's on purpose: the inflow is ramped over BIOFSI_FSI_RAMP
// seconds instead of 2, to reach the periodic state in fewer steps; the periodic state does not
// depend on how it was reached. For the same reason FSI2's flag gets a transverse push when the
// ramp ends (a body force rho_s a(t) on the flag, a(t) = kick sin^2(pi (t - t0) / 0.25 s) for a
// quarter second, half the expected period): from rest its swing would have to grow out of
// round-off, and the unseeded run would spend most of its steps reaching the state the benchmark
// measures. Estimated effect of 4 m/s^2 (impulse over flag plus broadside added mass, at 2 Hz): a
// tip swing of ~0.015, which then grows to the periodic +-0.078.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ale/mesh_motion.hpp"
#include "coupling/fsi_benchmarks.hpp"
#include "coupling/mesh_transfer.hpp"
#include "coupling/oscillation.hpp"
#include "environment.hpp"
#include "kernels/core/hex8.hpp"

using namespace biofsi;
using namespace biofsi::test;

namespace {

// drag and lift act on cylinder + flag (the benchmark's); drag_flag and lift_flag are the flag's
// part of them, to tell which body carries an error in the forces; px_flag and py_flag are the
// flag's momentum per unit depth, whose rate splits the flag's part into its inertia and the
// force through its root (NaN where a series file has no such columns).
struct Series {
  std::vector<double> t, ux, uy, drag, lift, drag_flag, lift_flag, px_flag, py_flag;
  std::vector<std::vector<double>*> columns() {
    return {&t, &ux, &uy, &drag, &lift, &drag_flag, &lift_flag, &px_flag, &py_flag};
  }
  void add(const std::vector<double>& row) {
    const auto c = columns();
    for (size_t k = 0; k < c.size(); ++k) c[k]->push_back(k < row.size() ? row[k] : NAN);
  }
  // Keeps the rows before time `end` (a resumed run drops what came after its checkpoint).
  void keep_before(double end) {
    size_t k = 0;
    while (k < t.size() && t[k] < end) ++k;
    for (auto* v : columns()) v->resize(k);
  }
};

// One stretch of a run, from where the previous one stopped to t_end: its step, its one-step-theta
// (fluid and structure) and the fluid mesh's stiffening.
struct Stage {
  double dt, theta, stiffening, t_end;
};

// A published result: mean +- amplitude [frequency] of each quantity the benchmark reports.
struct BenchmarkRow {
  Reference ux, uy, drag, lift;
};

struct UnsteadyCase {
  int number;  // 2 or 3
  FsiCase parameters;
  // Run from rest through these in turn, each continuing from the state the last one reached:
  // a start-up reached cheaply, the periodic state measured with the accurate scheme.
  std::vector<Stage> stages;
  double kick = 0;  // peak transverse acceleration of the seeding pulse [m/s^2]
  std::string mesh = "turek_hron_wake";
  // Each field's Newton tolerance relative to its largest residual in the step.
  double newton_tol = 1e-6;
  // The row the test checks (each case says which), and Turek & Hron (2006)'s summary row where
  // that is not the checked one: reported beside it.
  BenchmarkRow reference;
  std::optional<BenchmarkRow> row_2006;
};

UnsteadyCase fsi2() {
  UnsteadyCase c;
  c.number = 2;
  c.parameters.solid_density = 10000;
  c.parameters.solid_shear_modulus = 0.5e6;
  c.parameters.u_mean = 1;
  // Start-up: the ramp, the push and the growth of the swing with theta a little above
  // Crank-Nicolson and 25 steps per lift period; from t = 4.4 s Crank-Nicolson with 50 steps per
  // period, the periodic state that is measured. Why not 0.5 throughout: with dt 0.02 it cuts
  // steps at the extreme swings (in 10 of 21 steps, the lift jumping by ~100 from step to step).
  // Why not 0.52 throughout: it damps the periodic swing (u_y(A) by ~18%, the lift by ~25%). The
  // fluid mesh's stiffening is 3 from rest: with 2 the fluid cell beside the tip inverts at the
  // extreme swing (t ~ 3.14 s: minimum scaled Jacobian 0.59, 0.30, 0.06 over the three steps
  // before, then no line-search step without an inverted element); with 3 the first step from
  // rest takes 3 Newton and 20 Krylov iterations, as with 2.
  // Measured (these stages from rest, 440 steps, no cut step, 22-24 s a step on 2 threads): the
  // fluid mesh's smallest scaled Jacobian 0.308 (t = 5.95 s; >= 0.44 through the extreme swings at
  // t = 3.0-3.5 s); 2.9 Newton and 35 Krylov a step before 4.4 s, 3.2 and 44 after, 4.5 and 98
  // over t = 6.0-6.6 s, where the Newton count alternates 4/6 from step to step (the lift carries
  // a step-to-step zigzag of ~2, 1% of its amplitude). At t = 6.6 s: u_y(A) 1.26e-3 +- 7.78e-2
  // (-3.4%, amplitude change over the last period 0.00%) at 1.964 Hz (-1.8%), u_x(A) -1.38e-2 +-
  // 1.20e-2 (mean -5.3%, amplitude -3.5%) at 3.93 Hz (+3.4%), drag 206.4 +- 68.9 (mean -1.2%,
  // amplitude -6.6%) at 3.93 Hz (+3.5%), lift 0.64 +- 219.7 (-6.2%) at 1.969 Hz (-1.6%). The
  // lift's half-period peaks vary between 210 and 228 over t = 4.6-6.6 s, so one period's lift
  // amplitude moves by a few per cent with the end of the run. Flag/cylinder: lift +-244.0 /
  // +-61.4, partly out of phase; drag 57.6 +- 66.2 / 148.4 +- 3.7.
  c.stages = {{0.02, 0.52, 3, 4.4}, {0.01, 0.5, 3, 6.6}};
  c.kick = 4;
  // Checked against Turek & Hron (2006)'s FSI2 summary row (as nutils' examples/turek.py also
  // quotes it); unlike FSI3's, no finer row of the authors' is at hand here.
  c.reference = {{-1.4580e-2, 1.2440e-2, 3.8},
                 {1.2300e-3, 8.0600e-2, 2.0},
                 {2.0883e2, 7.3750e1, 3.8},
                 {8.8000e-1, 2.3420e2, 2.0}};
  return c;
}

UnsteadyCase fsi3() {
  UnsteadyCase c;
  c.number = 3;
  c.parameters.solid_density = 1000;
  c.parameters.solid_shear_modulus = 2e6;
  c.parameters.u_mean = 2;
  // On turek_hron_flag (refine 2's flag in the wake mesh; why: the header). Start-up with 19
  // steps per lift period, measured with 76: the swing grows from t ~ 1.7 s (u_y 0.039 at 2.54 s
  // in the dt 0.01 stage), and the 0.5 s at dt 0.0025 reach the periodic state (from t ~ 3.1 s)
  // and two periods in it. These stages from rest (490 steps) measured the header's numbers.
  c.mesh = "turek_hron_flag";
  c.stages = {{0.01, 0.5, 2, 2.9}, {0.0025, 0.5, 2, 3.4}};
  // 1e-4: against 1e-6 from rest to t = 1.37 s the largest differences are 4e-6 of u_y(A)'s and
  // 1.3e-4 of the lift's largest value, and in the periodic state the lift and drag amplitudes of
  // the two differ by less than either's spread from period to period; it saves a quarter of the
  // time.
  c.newton_tol = 1e-4;
  // Checked against the benchmark authors' finest FSI3 result: Featflow, level 4+0, dt = 0.00025 s,
  // the row of the reference time history published with the benchmark (Featflow FSI benchmark
  // reference page, TU Dortmund; Turek, Hron, Madlik, Razzaq, Wobker & Acker 2010, Fluid
  // Structure Interaction II, LNCSE 73). The 2006 proposal's summary row (as quoted by nutils'
  // examples/turek.py and solids4foam), reported beside it, differs from it most in the drag
  // amplitude, 22.66 against 27.74 (-18%): this run's drag amplitude is +18.6% against the 2006
  // row and -3.1% against this one (on a finer mesh it rises; see the header). Checks on the
  // finer row: the published history itself (t = 5.0455-5.228 s, one swing, read from
  // solids4foam's copy, tutorials/fluidSolidInteraction/HronTurekFsi3/verification/reference)
  // gives drag 460.1 +- 28.3, u_y 1.57e-3 +- 3.481e-2, u_x -2.87e-3 +- 2.72e-3; solids4foam's own
  // FSI3 study (finite volumes, partitioned, 2x mesh) measured drag 459.3 +- 28.06 against it.
  c.reference = {{-2.8800e-3, 2.7200e-3, 10.93},
                 {1.4700e-3, 3.4990e-2, 5.46},
                 {4.6050e2, 2.7740e1, 10.93},
                 {2.5000e0, 1.5391e2, 5.46}};
  c.row_2006 = BenchmarkRow{{-2.6900e-3, 2.5300e-3, 10.9},
                            {1.4800e-3, 3.4380e-2, 5.3},
                            {4.5730e2, 2.2660e1, 10.9},
                            {2.2200e0, 1.4978e2, 5.3}};
  return c;
}

std::string series_path(const std::string& folder, int number) {
  return folder + "/fsi" + std::to_string(number) + "_series.csv";
}

void write_row(std::ostream& out, Series& s, size_t i) {
  const char* separator = "";
  for (const auto* column : s.columns()) {
    out << separator << (*column)[i];
    separator = ",";
  }
  out << '\n';
}

// Writes the whole series (the start of a run, or a resumed run's rows so far).
void write_series(const std::string& folder, int number, Series& s) {
  std::ofstream out(series_path(folder, number), std::ios::trunc);
  out << "t,ux,uy,drag,lift,drag_flag,lift_flag,px_flag,py_flag\n";
  out.precision(10);
  for (size_t i = 0; i < s.t.size(); ++i) write_row(out, s, i);
}

// Appends the series' newest row, so a run stopped at any point leaves every finished step on
// disk without rewriting the file each step.
void append_last_row(const std::string& folder, int number, Series& s) {
  std::ofstream out(series_path(folder, number), std::ios::app);
  out.precision(10);
  write_row(out, s, s.t.size() - 1);
}

Series read_series(const std::string& path);

// The state after a step, enough to continue the run as if it had not stopped: structure
// displacement and velocity, fluid velocity and pressure, fluid mesh displacement and grid
// velocity (the next step's predictor), and the step's number and size. Binary, this machine's
// byte order: a run's own scratch file, not an exchange format.
constexpr char checkpoint_magic[] = "biofsi-fsi-unsteady-1";

void write_checkpoint(const std::string& path, const TurekHronFsi& th, int step, double dt) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    const int n = th.mesh.n_nodes();
    out.write(checkpoint_magic, sizeof checkpoint_magic);
    out.write(reinterpret_cast<const char*>(&n), sizeof n);
    out.write(reinterpret_cast<const char*>(&step), sizeof step);
    out.write(reinterpret_cast<const char*>(&dt), sizeof dt);
    auto points = [&out](const std::vector<Point>& v) {
      out.write(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(Point));
    };
    points(th.structure->displacement());
    points(th.structure->velocity());
    points(th.fsi->mesh_displacement());
    points(th.fsi->grid_velocity());
    const std::vector<double> f = th.fluid->solution_host();
    out.write(reinterpret_cast<const char*>(f.data()), f.size() * sizeof(double));
    if (!out) ADD_FAILURE() << path << ": could not write the checkpoint";
  }
  std::rename(tmp.c_str(), path.c_str());  // a run killed while writing keeps the last one
}

// The leading fields of a checkpoint (write_checkpoint), read from `in`.
struct CheckpointHeader {
  int nodes = 0, step = 0;
  double dt = 0;
};

CheckpointHeader read_checkpoint_header(std::ifstream& in, const std::string& path) {
  char magic[sizeof checkpoint_magic] = {};
  CheckpointHeader h;
  in.read(magic, sizeof magic);
  in.read(reinterpret_cast<char*>(&h.nodes), sizeof h.nodes);
  in.read(reinterpret_cast<char*>(&h.step), sizeof h.step);
  in.read(reinterpret_cast<char*>(&h.dt), sizeof h.dt);
  if (!in || std::string(magic) != checkpoint_magic)
    throw std::runtime_error(path + ": not a checkpoint of test_fsi_unsteady");
  return h;
}

// A checkpoint's nodal state: structure displacement and velocity, fluid mesh displacement and
// velocity, fluid (u, v, w, p) per node.
struct CheckpointState {
  std::vector<Point> d, v, g, w;
  std::vector<double> fluid;
};

// The state of mesh `from` on mesh `to` (same case, another discretisation), interpolated in the
// reference configuration: the structure's fields from the solid elements, the fluid's and the
// fluid mesh's from the fluid elements. Both meshes' fluid meshes then carry the same
// displacement, so interpolating the fluid's (u, p) at a node's reference position takes it from
// the same deformed point up to the map's variation inside one element. Walls and the clamp are
// set to their exact values (a cylinder node of one mesh lies off the other's chords), and on the
// interface the fluid mesh and the fluid follow the structure exactly. The velocity is not
// divergence-free on the new mesh: the first steps' pressure absorbs that (a transient to leave out
// of the analysis).
CheckpointState transfer(const Mesh& from, const CheckpointState& s, const Mesh& to) {
  const int solid_from = from.block_index("solid"), fluid_from = from.block_index("fluid");
  const int solid_to = to.block_index("solid"), fluid_to = to.block_index("fluid");
  if (solid_from < 0 || fluid_from < 0 || solid_to < 0 || fluid_to < 0)
    throw std::runtime_error("mesh transfer: both meshes need the blocks 'solid' and 'fluid'");
  const NodalInterpolator solid(from, from.elements_of_block(solid_from));
  const NodalInterpolator fluid(from, from.elements_of_block(fluid_from));
  const size_t n = to.n_nodes();
  CheckpointState out{std::vector<Point>(n, Point{0, 0, 0}), std::vector<Point>(n, Point{0, 0, 0}),
                      std::vector<Point>(n, Point{0, 0, 0}), std::vector<Point>(n, Point{0, 0, 0}),
                      std::vector<double>(4 * n, 0.0)};
  for (int a : to.nodes_of_block(solid_to)) {
    const NodalWeights w = solid.locate(to.x[a]);
    out.d[a] = solid.interpolate(w, s.d);
    out.v[a] = solid.interpolate(w, s.v);
  }
  std::vector<std::array<double, 4>> f_from(from.n_nodes());
  for (int a = 0; a < from.n_nodes(); ++a)
    for (int k = 0; k < 4; ++k) f_from[a][k] = s.fluid[4 * a + k];
  for (int a : to.nodes_of_block(fluid_to)) {
    const NodalWeights w = fluid.locate(to.x[a]);
    out.g[a] = fluid.interpolate(w, s.g);
    out.w[a] = fluid.interpolate(w, s.w);
    for (int k = 0; k < 4; ++k) {
      double value = 0;
      const auto& c = from.conn[w.element];
      for (int b = 0; b < 8; ++b) value += w.n[b] * f_from[c[b]][k];
      out.fluid[4 * a + k] = value;
    }
  }
  const Point zero{0, 0, 0};
  for (const char* wall : {"walls", "cylinder", "inflow", "outflow"})
    for (int a : to.node_sets.at(wall)) out.g[a] = out.w[a] = zero;
  for (const char* wall : {"walls", "cylinder"})
    for (int a : to.node_sets.at(wall))
      for (int k = 0; k < 3; ++k) out.fluid[4 * a + k] = 0;
  for (int a : to.node_sets.at("solid_clamp")) out.d[a] = out.v[a] = zero;
  // On the interface the checkpoints hold g = d and the fluid's velocity = v (the grid velocity
  // is the time scheme's difference quotient, not v).
  for (int a : to.node_sets.at("fsi")) {
    out.g[a] = out.d[a];
    for (int k = 0; k < 3; ++k) out.fluid[4 * a + k] = out.v[a][k];
  }
  return out;
}

// Restores a checkpoint of the same case and mesh (or, with BIOFSI_FSI_RESTART_MESH naming the
// mesh it was written on, of another mesh of the case: transfer); returns the number of steps of
// size dt that reach its time, which may have been reached with another step size (a time-step
// study from a periodic state: one-step-theta needs only the state at t_n).
int read_checkpoint(const std::string& path, TurekHronFsi& th, double dt) {
  std::ifstream in(path, std::ios::binary);
  const CheckpointHeader h = read_checkpoint_header(in, path);
  const int n = h.nodes;
  // Only a checkpoint of another mesh is moved: the stages after the first restart from this
  // run's own.
  const char* restart_mesh =
      n != th.mesh.n_nodes() ? std::getenv("BIOFSI_FSI_RESTART_MESH") : nullptr;
  if (!restart_mesh && n != th.mesh.n_nodes())
    throw std::runtime_error(path + ": written for " + std::to_string(n) +
                             " nodes, this run's mesh has " + std::to_string(th.mesh.n_nodes()) +
                             " (BIOFSI_FSI_RESTART_MESH names the checkpoint's mesh)");
  const double t = h.step * h.dt;
  const int step = static_cast<int>(std::lround(t / dt));
  if (std::abs(step * dt - t) > 1e-9 * t)
    throw std::runtime_error(
        path + ": its time " + std::to_string(t) +
        " is not a whole number of steps of BIOFSI_FSI_DT = " + std::to_string(dt));
  auto points = [&in, n]() {
    std::vector<Point> v(n);
    in.read(reinterpret_cast<char*>(v.data()), v.size() * sizeof(Point));
    return v;
  };
  const auto d = points(), v = points(), g = points(), w = points();
  std::vector<double> f(4 * static_cast<size_t>(n));
  in.read(reinterpret_cast<char*>(f.data()), f.size() * sizeof(double));
  if (!in) throw std::runtime_error(path + ": the checkpoint is truncated");
  CheckpointState state{d, v, g, w, f};
  if (restart_mesh) {
    const Mesh from = read_gmsh(mesh_file(restart_mesh), benchmark_thickness);
    if (from.n_nodes() != n)
      throw std::runtime_error(path + ": written for " + std::to_string(n) +
                               " nodes, BIOFSI_FSI_RESTART_MESH = '" + restart_mesh + "' has " +
                               std::to_string(from.n_nodes()));
    state = transfer(from, state, th.mesh);
    std::printf("FSI: checkpoint %s moved from %s (%d nodes) to this run's mesh (%d nodes)\n",
                path.c_str(), restart_mesh, n, th.mesh.n_nodes());
  }
  th.structure->set_state(state.d, state.v, t);
  th.fluid->set_solution(state.fluid);
  th.fluid->set_time(t);
  th.fsi->set_mesh_displacement(state.g, state.w);
  return step;
}

// BIOFSI_FSI_STAGES: "dt,theta,stiffening,t_end;..." (t_end increasing), or none.
std::vector<Stage> stages_from_environment() {
  const char* text = std::getenv("BIOFSI_FSI_STAGES");
  std::vector<Stage> out;
  if (!text) return out;
  std::stringstream all(text);
  std::string item;
  while (std::getline(all, item, ';')) {
    Stage st;
    char c1 = 0, c2 = 0, c3 = 0;
    std::stringstream one(item);
    if (!(one >> st.dt >> c1 >> st.theta >> c2 >> st.stiffening >> c3 >> st.t_end) || c1 != ',' ||
        c2 != ',' || c3 != ',' || !(st.dt > 0) || !(st.theta >= 0.5 && st.theta <= 1) ||
        (!out.empty() && !(st.t_end > out.back().t_end)))
      throw std::runtime_error("BIOFSI_FSI_STAGES: '" + item +
                               "' is not dt,theta,stiffening,t_end with dt > 0, theta in "
                               "[0.5, 1] and t_end after the previous stage's");
    out.push_back(st);
  }
  return out;
}

// The case's stages (or BIOFSI_FSI_STAGES) cut at BIOFSI_FSI_T_END; or, when BIOFSI_FSI_DT,
// BIOFSI_FSI_THETA or BIOFSI_FSI_STIFFENING is set, one stage with those values (the others from
// the last stage).
std::vector<Stage> stages_of(UnsteadyCase c) {
  const std::vector<Stage> given = stages_from_environment();
  if (!given.empty()) c.stages = given;
  const double t_end = env_or("BIOFSI_FSI_T_END", c.stages.back().t_end);
  const Stage& last = c.stages.back();
  if (std::getenv("BIOFSI_FSI_DT") || std::getenv("BIOFSI_FSI_THETA") ||
      std::getenv("BIOFSI_FSI_STIFFENING"))
    return {{env_or("BIOFSI_FSI_DT", last.dt), env_or("BIOFSI_FSI_THETA", last.theta),
             env_or("BIOFSI_FSI_STIFFENING", last.stiffening), t_end}};
  std::vector<Stage> out;
  for (Stage st : c.stages) {
    st.t_end = std::min(st.t_end, t_end);
    out.push_back(st);
    if (st.t_end >= t_end) break;
  }
  return out;
}

// The time a checkpoint was written at.
double checkpoint_time(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const CheckpointHeader h = read_checkpoint_header(in, path);
  return h.step * h.dt;
}

std::unique_ptr<TurekHronFsi> build(const UnsteadyCase& c, const Stage& stage) {
  const double ramp_time = env_or("BIOFSI_FSI_RAMP", 0.5);
  const double stiffening = stage.stiffening;
  auto th = make_turek_hron(
      env_or("BIOFSI_FSI_MESH", c.mesh), c.parameters, false, stage.theta,
      ShapeDerivatives::FiniteDifference,
      [stiffening, &c](FsiSettings& s) {
        // Every field to c.newton_tol of its largest residual in the step: the step's own
        // discretisation error is far larger.
        s.rel_tol = env_or("BIOFSI_FSI_NEWTON_TOL", c.newton_tol);
        s.inner_tolerance = env_or("BIOFSI_FSI_INNER_TOL", 1e-2);
        // The flag's swing (FSI2: 0.08 at the tip) squeezes the fluid cells around it. A
        // prescribed bending shape moved the refine-1 mesh to a minimum scaled Jacobian of
        // 0.58 / 0.28 / 0.008 at tip 0.05 / 0.07 / 0.09 with the default (1/det J)^1
        // stiffening, 0.66 / 0.64 / 0.56 with the square.
        s.mesh_motion.stiffening = stiffening;
      },
      [](FluidSettings& f) {
        f.transient_tau = env_or("BIOFSI_FSI_STEADY_TAU", 0) == 0;
        // SIMPLEC: at FSI3's Re 200 and CFL ~6 the fluid block needed ~12 inner
        // iterations per outer one where SIMPLE needed 30-40 (diag(A) no longer
        // stands for a convection-dominated A; its row sums do better).
        f.preconditioner = env_or("BIOFSI_FSI_SIMPLE", 0) != 0 ? FluidPreconditioner::Simple
                                                               : FluidPreconditioner::SimpleC;
      });
  th->ramp = [ramp_time](double t) {
    return t < ramp_time ? 0.5 * (1 - std::cos(M_PI * t / ramp_time)) : 1.0;
  };
  const double kick = env_or("BIOFSI_FSI_KICK", c.kick);
  if (kick != 0) {
    const double force = c.parameters.solid_density * kick, t0 = ramp_time, width = 0.25;
    const SpaceTimeFunction zero = [](const Point&, double) { return 0.0; };
    th->structure->set_body_force({zero,
                                   [=](const Point&, double t) {
                                     if (t <= t0 || t >= t0 + width) return 0.0;
                                     const double s = std::sin(M_PI * (t - t0) / width);
                                     return force * s * s;
                                   },
                                   zero});
  }
  return th;
}

// Where a step's time went (BIOFSI_FSI_VERBOSE): the inner block solves per field, which are most
// of it, and the rest by phase.
void print_step_cost(const FsiStats& before, const FsiStats& after) {
  const char* field[] = {"structure", "fluid", "mesh"};
  std::printf("    inner Krylov (iterations, s):");
  for (int b = 0; b < 3; ++b)
    std::printf(" %s %d, %.1f;", field[b], after.inner_iterations[b] - before.inner_iterations[b],
                after.seconds_inner[b] - before.seconds_inner[b]);
  std::printf(
      " residual %.1f s, Jacobian action %.1f s (shape derivatives %.1f s), assembly %.1f s, "
      "preconditioner set-up %.1f s\n",
      after.seconds_residual - before.seconds_residual,
      after.seconds_tangent - before.seconds_tangent, after.seconds_shape - before.seconds_shape,
      after.seconds_assembly - before.seconds_assembly,
      after.seconds_preconditioner_setup - before.seconds_preconditioner_setup);
}

// int_solid rho_s N_a dV per node a (zero off the solid): with it, sum_a m_a v_a is the discrete
// structure's momentum exactly, since the consistent mass's rows sum to it.
std::vector<double> solid_nodal_mass(const Mesh& mesh, double density) {
  std::vector<double> m(mesh.n_nodes(), 0.0);
  for (int e : mesh.elements_of_block(mesh.block_index("solid"))) {
    const auto& c = mesh.conn[e];
    Real xe[Hex8::n_nodes][3];
    for (int l = 0; l < Hex8::n_nodes; ++l)
      for (int d = 0; d < 3; ++d) xe[l][d] = mesh.x[c[vtk_of_lex(l)]][d];
    ElementGeometry<Hex8> geometry;
    geometry.compute(xe);
    for (int l = 0; l < Hex8::n_nodes; ++l)
      for (int q = 0; q < Hex8::n_qp; ++q) {
        Real n, unused_gradient[3];
        basis_at_point<Hex8>(l, q, n, unused_gradient);
        m[c[vtk_of_lex(l)]] += density * n * geometry.wdet[q];
      }
  }
  return m;
}

// The flag's momentum per unit depth. With the structure's one-step-theta its change over a step
// is dt times the theta-average of the forces on the flag (fluid and root), which the analysis
// uses to split the fluid's force on the flag.
Point flag_momentum(const TurekHronFsi& th, const std::vector<double>& mass) {
  const std::vector<Point> v = th.structure->velocity();
  Point p{0, 0, 0};
  for (size_t a = 0; a < v.size(); ++a)
    for (int d = 0; d < 3; ++d) p[d] += mass[a] * v[a][d] / benchmark_thickness;
  return p;
}

// Steps a built problem from step `first` to the end of its stage, appending to the series;
// false if an element inverted (reported).
bool advance(const UnsteadyCase& c, TurekHronFsi& th, double dt, int first, int last, Series& s) {
  const std::vector<double> flag_mass = solid_nodal_mass(th.mesh, c.parameters.solid_density);
  const char* folder = std::getenv("BIOFSI_FSI_SERIES");
  const char* checkpoint = std::getenv("BIOFSI_FSI_CHECKPOINT");
  const int checkpoint_every = static_cast<int>(env_or("BIOFSI_FSI_CHECKPOINT_EVERY", 10));
  const bool verbose = env_or("BIOFSI_FSI_VERBOSE", 0) != 0;
  for (int i = first; i <= last; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const FsiStats before = verbose ? th.fsi->stats() : FsiStats{};  // for print_step_cost
    const NewtonResult r =
        th.fsi->step(dt, "FSI" + std::to_string(c.number) + " step " + std::to_string(i));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const TurekHronFsi::ForceParts parts = th.force_parts();
    const Point f = parts.total();
    const double ux = th.tip_displacement(0), uy = th.tip_displacement(1);
    const Mesh current = th.fsi->current_mesh();
    const std::vector<QualityRange> quality = mesh_quality_by_block(current);
    std::printf(
        "FSI%d t %.4f: %d Newton, %d Krylov, %.1f s; u_x %.4e u_y %.4e drag %.2f lift %.2f; "
        "min scaled Jacobian",
        c.number, i * dt, r.iterations, r.krylov_iterations, seconds, ux, uy, f[0], f[1]);
    for (size_t b = 0; b < quality.size(); ++b)
      if (quality[b].worst_element >= 0)
        std::printf(" %s %.3f", th.mesh.block_names[b].c_str(), quality[b].min);
    std::printf("; %d cut steps so far\n", th.fsi->stats().cut_steps);
    if (verbose) {  // the step's (last attempt's) Newton history: residual norms per field
      const FsiStats& st = th.fsi->stats();
      for (size_t k = 0; k < st.last_residuals.size(); ++k)
        std::printf("    Newton %zu: structure %.3e fluid %.3e mesh %.3e%s\n", k,
                    st.last_residuals[k][0], st.last_residuals[k][1], st.last_residuals[k][2],
                    k < st.last_krylov.size()
                        ? (", then " + std::to_string(st.last_krylov[k]) + " Krylov").c_str()
                        : "");
      print_step_cost(before, st);
    }
    std::fflush(stdout);
    // The fields do not check the deformed mesh (the scene driver does): stop here, with the
    // step named, rather than integrate on an inverted element.
    for (size_t b = 0; b < quality.size(); ++b)
      if (quality[b].worst_element >= 0 && !(quality[b].min > 0)) {
        const int e = quality[b].worst_element;
        std::ostringstream corners;  // reference -> current position of its z = 0 nodes
        for (int k = 0; k < 8; ++k) {
          const int n = th.mesh.conn[e][k];
          if (th.mesh.x[n][2] != 0) continue;
          corners << " (" << th.mesh.x[n][0] << ", " << th.mesh.x[n][1] << ") -> ("
                  << current.x[n][0] << ", " << current.x[n][1] << ")";
        }
        ADD_FAILURE() << "FSI" << c.number << " step " << i << " (t = " << i * dt
                      << "): " << th.mesh.block_names[b] << " element " << e
                      << " inverted (scaled Jacobian " << quality[b].min
                      << "); its nodes:" << corners.str();
        return false;
      }
    const Point p = flag_momentum(th, flag_mass);
    s.add({i * dt, ux, uy, f[0], f[1], parts.flag[0], parts.flag[1], p[0], p[1]});
    if (folder) append_last_row(folder, c.number, s);
    if (checkpoint && i % checkpoint_every == 0) write_checkpoint(checkpoint, th, i, dt);
  }
  return true;
}

Series run(const UnsteadyCase& c) {
  const std::vector<Stage> stages = stages_of(c);
  const char* folder = std::getenv("BIOFSI_FSI_SERIES");
  const char* restart = std::getenv("BIOFSI_FSI_RESTART");
  // A resumed run starts in the stage its checkpoint's time falls in.
  std::string resume_from = restart ? restart : "";
  size_t k = 0;
  if (restart) {
    const double t = checkpoint_time(restart);
    while (k + 1 < stages.size() && t >= stages[k].t_end - 1e-9) ++k;
  }
  Series s;
  for (bool first_here = true; k < stages.size(); ++k, first_here = false) {
    const Stage& stage = stages[k];
    auto th = build(c, stage);
    int first = 1;
    if (!resume_from.empty()) {
      first = read_checkpoint(resume_from, *th, stage.dt) + 1;
      if (first_here && folder && !std::getenv("BIOFSI_FSI_RESTART_MESH")) {
        // The resumed run's series continues the one its checkpoints came from (a run moved to
        // another mesh starts a series of its own).
        s = read_series(series_path(folder, c.number));
        s.keep_before((first - 0.5) * stage.dt);
      }
      std::printf("FSI%d: stage %zu (dt %g, theta %g, stiffening %g) from %s at t = %.4f\n",
                  c.number, k + 1, stage.dt, stage.theta, stage.stiffening, resume_from.c_str(),
                  (first - 1) * stage.dt);
    }
    if (folder && first_here) write_series(folder, c.number, s);
    const int last = static_cast<int>(std::lround(stage.t_end / stage.dt));
    if (!advance(c, *th, stage.dt, first, last, s)) return s;
    if (k + 1 < stages.size()) {
      // The next stage's problem (another theta) continues from this one's final state.
      resume_from = ::testing::TempDir() + "fsi" + std::to_string(c.number) + "_stage.bin";
      write_checkpoint(resume_from, *th, last, stage.dt);
    }
  }
  return s;
}

// A series written by an earlier run (BIOFSI_FSI_SERIES), for analysing a run stopped early.
Series read_series(const std::string& path) {
  std::ifstream in(path);
  Series s;
  if (!in) {
    ADD_FAILURE() << "BIOFSI_FSI_FROM_SERIES = '" << path << "': cannot open the file";
    return s;
  }
  std::string line;
  std::getline(in, line);  // header t,ux,uy,drag,lift[,drag_flag,lift_flag[,px_flag,py_flag]]
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) row.push_back(std::stod(field));
    if (row.size() >= 5) s.add(row);  // the flag's columns are optional
  }
  if (s.t.empty())
    ADD_FAILURE() << "BIOFSI_FSI_FROM_SERIES = '" << path << "': no rows t,ux,uy,drag,lift";
  return s;
}

// The fluid's force on the flag split by the flag's momentum balance: per step, the momentum's
// change over dt (the flag's inertia) is the fluid's force of that step (the structure and the
// fluid see the same theta-weighted interface force) plus the force through the root.
void report_flag_balance(const Series& s, double t_from) {
  std::vector<double> t, inertia[2], root[2];
  for (size_t i = 1; i < s.t.size(); ++i) {
    const double dt = s.t[i] - s.t[i - 1];
    if (s.t[i] < t_from || !(dt > 0) || !std::isfinite(s.px_flag[i - 1]) ||
        !std::isfinite(s.px_flag[i]))
      continue;
    const double rate[2] = {(s.px_flag[i] - s.px_flag[i - 1]) / dt,
                            (s.py_flag[i] - s.py_flag[i - 1]) / dt};
    const double fluid[2] = {s.drag_flag[i], s.lift_flag[i]};
    t.push_back(s.t[i] - 0.5 * dt);
    for (int d = 0; d < 2; ++d) {
      inertia[d].push_back(rate[d]);
      root[d].push_back(rate[d] - fluid[d]);
    }
  }
  if (t.size() < 8) return;  // no momentum columns in the analysed window
  report("flag's x-momentum rate", analyse(t, inertia[0], t_from, 4));
  report("x-force through the flag's root", analyse(t, root[0], t_from, 4));
  report("flag's y-momentum rate", analyse(t, inertia[1], t_from, 4));
  report("y-force through the flag's root", analyse(t, root[1], t_from, 4));
}

void check(const UnsteadyCase& c) {
  const char* from = std::getenv("BIOFSI_FSI_FROM_SERIES");
  const Series s = from ? read_series(from) : run(c);
  ASSERT_FALSE(s.t.empty());
  // The last third of the run: past the ramp and the growth of the oscillation.
  const double t_from = s.t.back() * 2.0 / 3.0;
  const Oscillation ux = analyse(s.t, s.ux, t_from, 4), uy = analyse(s.t, s.uy, t_from, 4);
  const Oscillation drag = analyse(s.t, s.drag, t_from, 4), lift = analyse(s.t, s.lift, t_from, 4);
  auto report_row = [&](const BenchmarkRow& row, const std::string& which) {
    report_against(("u_x(A)" + which).c_str(), ux, row.ux);
    report_against(("u_y(A)" + which).c_str(), uy, row.uy);
    report_against(("drag" + which).c_str(), drag, row.drag);
    report_against(("lift" + which).c_str(), lift, row.lift);
  };
  report_row(c.reference, "");
  if (c.row_2006) report_row(*c.row_2006, ", against the 2006 summary");
  // Which body carries the forces' error: the flag's part is tied to the flag's own motion
  // (its inertia less its root's shear force), the cylinder's is the wake's.
  auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (finite(s.drag_flag) && finite(s.lift_flag)) {
    std::vector<double> drag_cylinder(s.t.size()), lift_cylinder(s.t.size());
    for (size_t i = 0; i < s.t.size(); ++i) {
      drag_cylinder[i] = s.drag[i] - s.drag_flag[i];
      lift_cylinder[i] = s.lift[i] - s.lift_flag[i];
    }
    report("drag on the flag", analyse(s.t, s.drag_flag, t_from, 4));
    report("drag on the cylinder", analyse(s.t, drag_cylinder, t_from, 4));
    report("lift on the flag", analyse(s.t, s.lift_flag, t_from, 4));
    report("lift on the cylinder", analyse(s.t, lift_cylinder, t_from, 4));
  }
  report_flag_balance(s, t_from);
  ASSERT_GE(uy.periods, 3) << "no periodic oscillation in the analysed window";
  // A swing still growing (or decaying) is not the periodic state the benchmark reports: the
  // last two periods' amplitudes within 3% (the growth seen on the way was 10-70% per period;
  // Crank-Nicolson's step-to-step jitter moves a sampled extreme by ~1%).
  EXPECT_LT(std::abs(uy.amplitude_change), 0.03) << "u_y(A) not yet periodic";
  // Tolerances, and why: the frequency is what a coarse mesh and ~20 steps per period keep best
  // (Crank-Nicolson's phase error at omega dt = 0.33 is ~1%, the flag's stiffness on 4 elements
  // through its thickness ~3% as in FSI1); 5%. The amplitudes carry the mesh's error in the
  // wake and the flag's bending: 15%. The means of u_y and lift are small differences of large
  // swings (the reference's own levels disagree in that digit), so only drag's mean, 5%.
  const BenchmarkRow& r = c.reference;
  EXPECT_NEAR(uy.frequency, r.uy.frequency, 0.05 * r.uy.frequency);
  EXPECT_NEAR(lift.frequency, r.lift.frequency, 0.05 * r.lift.frequency);
  EXPECT_NEAR(ux.frequency, r.ux.frequency, 0.05 * r.ux.frequency);
  EXPECT_NEAR(uy.amplitude, r.uy.amplitude, 0.15 * r.uy.amplitude);
  EXPECT_NEAR(ux.amplitude, r.ux.amplitude, 0.15 * r.ux.amplitude);
  EXPECT_NEAR(lift.amplitude, r.lift.amplitude, 0.15 * r.lift.amplitude);
  EXPECT_NEAR(drag.amplitude, r.drag.amplitude, 0.15 * r.drag.amplitude);
  EXPECT_NEAR(drag.mean, r.drag.mean, 0.05 * r.drag.mean);
}

}  // namespace

TEST(FsiUnsteadyLong, TurekHronFsi2) { check(fsi2()); }

TEST(FsiUnsteadyLong, TurekHronFsi3) { check(fsi3()); }
