// moreau against IPOPT on the arm model (thesis 9.2, examples/control/arm_2d.toml).
// IPOPT solves the primal problem of tracking_nlp.h (exact first and second derivatives, MUMPS);
// moreau solves the Symplectic Pontryagin system of the same discretisation, whose KKT system
// it is. Both run at the target parameters; the controls, the value and the duals are compared.
//
//   ipopt_bench [--steps 256,512,1024,2048,4096] [--tol 1e-10] [--obj-scaling 1e3] [--verbose]
//   ipopt_bench --check      derivative checker (N = 8) and agreement at N = 64; exit 1 on failure
//   ipopt_bench --window [--recording FILE] [--ipopt-seconds 120]   every gap-filling window of
//                            a real recording (default shared/data/mocap/Vicon.c3d): moreau as
//                            the fill solves it, IPOPT (CPU time capped) on the same target
//                            problem from the same warm start
//
// One line per N and solver: seconds, iterations, and the differences to moreau's solution from
// the documented start (max |ΔL| over all controls, |ΔJ| / |J|, max |Δρ|).
#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "../arm_documented_start.h"
#include "fill_window.h"
#include "moreau/common/stopwatch.h"
#include "moreau/control/continuation.h"
#include "moreau/control/examples.h"
#include "moreau/control/newton.h"
#include "tracking_nlp.h"

namespace {

using namespace moreau;

double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
using namespace moreau::control;

// A solution in the primal variables: controls (springs × N), duals ρ^1 … ρ^N (n_z × N), value.
struct Solution {
  bool ok = false;
  double seconds = 0.0;      // wall clock
  double cpu_seconds = 0.0;  // process CPU time (robust against other load on the machine)
  int iterations = 0;
  Eigen::MatrixXd states, controls, duals;
  double value = 0.0;
};

Solution FromMoreau(const PontryaginDiscretization& disc, const Eigen::VectorXd& y) {
  Solution s;
  PontryaginWorkspace ws;
  s.controls = EffectiveControls(disc, y);
  s.value = DiscreteValue(disc, y, ws);
  Eigen::MatrixXd rho;
  disc.Unpack(y, s.states, rho);
  s.duals = rho.rightCols(disc.steps());
  return s;
}

Solution SolveMoreau(const ProblemFamily& family, int steps, const ContinuationOptions& options) {
  const PontryaginDiscretization disc(family(1.0), steps);
  Eigen::VectorXd y;
  const double cpu = CpuSeconds();
  const ContinuationSummary summary = SolveWithContinuation(family, steps, options, y);
  const double cpu_seconds = CpuSeconds() - cpu;
  Solution s = FromMoreau(disc, y);
  s.cpu_seconds = cpu_seconds;
  s.ok = summary.ok();
  s.seconds = summary.total_seconds;
  s.iterations = summary.newton_iterations;
  return s;
}

// IPOPT's print level: 0, or 5 with timing statistics (--verbose).
int g_print_level = 0;
// IPOPT's obj_scaling_factor (--obj-scaling). The arm's value is ≈ 1.1e−4 and IPOPT's tolerances
// are absolute in the scaled problem: scaled by 10³, tol 1e−10 gives controls within ≈ 1e−10
// of moreau's; unscaled, within ≈ 1e−7 (docs/benchmarks.md).
double g_obj_scaling = 1e3;
// --window: IPOPT's CPU time limit per window (--ipopt-seconds).
double g_window_cpu_seconds = 120.0;

Ipopt::SmartPtr<Ipopt::IpoptApplication> MakeIpopt(double tol) {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetNumericValue("tol", tol);
  app->Options()->SetNumericValue("obj_scaling_factor", g_obj_scaling);
  app->Options()->SetStringValue("hessian_approximation", "exact");
  app->Options()->SetStringValue("linear_solver", "mumps");
  app->Options()->SetIntegerValue("print_level", g_print_level);
  if (g_print_level > 0) app->Options()->SetStringValue("print_timing_statistics", "yes");
  app->Options()->SetIntegerValue("max_iter", 3000);
  // The entropy penalty is undefined outside [L−, L+]: keep IPOPT inside the true bounds.
  app->Options()->SetNumericValue("bound_relax_factor", 0.0);
  app->Options()->SetStringValue("sb", "yes");
  return app;
}

// IPOPT's start: the reference trajectory for the states, and the effective controls moreau's
// Newton starts from at the target parameters (fixed-point sweep on the reference guess).
Ipopt::SmartPtr<bench::TrackingNlp> MakeNlp(const PontryaginDiscretization& disc) {
  const Eigen::MatrixXd guess = ReferenceGuess(disc);
  Eigen::VectorXd y;
  FixedPointSweep(disc, guess, FixedPointOptions{}, y);
  return new bench::TrackingNlp(disc, guess, EffectiveControls(disc, y));
}

// IPOPT's max_cpu_time in seconds (0: IPOPT's default).
Solution SolveIpopt(const Ipopt::SmartPtr<bench::TrackingNlp>& nlp, double tol,
                    double cpu_limit = 0.0) {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = MakeIpopt(tol);
  if (cpu_limit > 0.0) app->Options()->SetNumericValue("max_cpu_time", cpu_limit);
  Stopwatch clock;
  const double cpu = CpuSeconds();
  Solution s;
  if (app->Initialize() != Ipopt::Solve_Succeeded) return s;
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(nlp);
  s.seconds = clock.Seconds();
  s.cpu_seconds = CpuSeconds() - cpu;
  s.ok = status == Ipopt::Solve_Succeeded;
  s.iterations = app->Statistics()->IterationCount();
  s.controls = nlp->controls();
  s.duals = nlp->duals();
  s.value = nlp->objective();
  return s;
}

void PrintLine(int steps, const char* solver, const Solution& s, const Solution& ref) {
  const bool comparable = s.controls.size() == ref.controls.size() && s.controls.size() > 0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::printf("%5d  %-18s %3s %8.3f %8.3f %5d  %.2e  %.2e  %.2e\n", steps, solver,
              s.ok ? "ok" : "BAD", s.seconds, s.cpu_seconds, s.iterations,
              comparable ? (s.controls - ref.controls).cwiseAbs().maxCoeff() : nan,
              comparable ? std::abs(s.value - ref.value) / std::abs(ref.value) : nan,
              comparable ? (s.duals - ref.duals).cwiseAbs().maxCoeff() : nan);
  std::fflush(stdout);
}

// IPOPT's derivative checker (first and second order, forward differences with its default
// perturbation 1e−8 and tolerance 1e−4) at moreau's solution for N = 8, every entry printed;
// reports the largest relative deviation per kind and returns true when nothing was flagged.
bool DerivativeCheck(const ProblemFamily& family) {
  const int steps = 8;
  const PontryaginDiscretization disc(family(1.0), steps);
  const Solution at = SolveMoreau(family, steps, moreau::bench::ArmDocumentedStart());
  Ipopt::SmartPtr<bench::TrackingNlp> nlp = new bench::TrackingNlp(disc, at.states, at.controls);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = MakeIpopt(1e-8);
  const std::string log = "ipopt_derivative_check.txt";
  app->Options()->SetStringValue("derivative_test", "second-order");
  app->Options()->SetStringValue("derivative_test_print_all", "yes");
  app->Options()->SetNumericValue("point_perturbation_radius", 0.0);
  app->Options()->SetStringValue("output_file", log);
  app->Options()->SetIntegerValue("file_print_level", 4);
  app->Options()->SetIntegerValue("max_iter", 0);
  app->Initialize();
  app->OptimizeTNLP(nlp);
  std::ifstream in(log);
  std::string line;
  int flagged = 0;
  bool clean = false;
  const char* kinds[] = {"grad_f", "jac_g", "obj_hess", "constr_hess"};
  double worst[4] = {0.0, 0.0, 0.0, 0.0};
  int entries[4] = {0, 0, 0, 0};
  while (std::getline(in, line)) {
    if (line.find("No errors detected by derivative checker") != std::string::npos) clean = true;
    if (line.rfind("*", 0) == 0) ++flagged;
    const std::size_t open = line.rfind('[');
    for (int k = 0; k < 4; ++k) {
      if (line.find(kinds[k]) == std::string::npos || open == std::string::npos) continue;
      worst[k] = std::max(worst[k], std::stod(line.substr(open + 1)));
      ++entries[k];
    }
  }
  std::printf("derivative checker (N = %d at moreau's solution, IPOPT defaults): %s, %d flagged\n",
              steps, clean ? "no errors" : "ERRORS", flagged);
  for (int k = 0; k < 4; ++k) {
    std::printf("  %-11s %5d entries, largest relative deviation %.2e\n", kinds[k], entries[k],
                worst[k]);
  }
  return clean && flagged == 0;
}

int Check(const ProblemFamily& family) {
  bool ok = DerivativeCheck(family);
  const int steps = 64;
  const PontryaginDiscretization disc(family(1.0), steps);
  const Solution ref = SolveMoreau(family, steps, moreau::bench::ArmDocumentedStart());
  const Solution ip = SolveIpopt(MakeNlp(disc), 1e-10);
  PrintLine(steps, "moreau documented", ref, ref);
  PrintLine(steps, "ipopt", ip, ref);
  const double dl = (ip.controls - ref.controls).cwiseAbs().maxCoeff();
  const double dj = std::abs(ip.value - ref.value) / std::abs(ref.value);
  const double drho =
      (ip.duals - ref.duals).cwiseAbs().maxCoeff() / ref.duals.cwiseAbs().maxCoeff();
  const bool agree = ref.ok && ip.ok && dl < 1e-6 && dj < 1e-8 && drho < 1e-6;
  std::printf(
      "agreement at N = %d (max|dL| < 1e-6, |dJ|/J < 1e-8, max|drho|/max|rho| < 1e-6): %s\n", steps,
      agree ? "yes" : "NO");
  ok = ok && agree;
  return ok ? 0 : 1;
}

// One window: moreau exactly as the fill solves it (MakeOcpWindowProblem, SolveOcpWindowProblem;
// checked against SolveOcpWindow's positions), IPOPT on its target problem from its warm start
// (states and effective controls at the target γ), objective scaled by 1 / |J| (J: moreau's
// value; 1 where moreau failed) unless --obj-scaling was given.
bool SolveWindow(const moreau::bench::FillWindows& fill, std::size_t index,
                 const mocap::OcpFillOptions& o, double tol, bool scaling_given) {
  const mocap::internal::OcpWindow& w = fill.windows[index];
  mocap::internal::OcpWindowProblem p;
  mocap::internal::MakeOcpWindowProblem(fill.in, fill.base, fill.network, w, o, p);
  const PontryaginDiscretization disc(*p.target, p.steps);
  std::printf("# %s: %d anchors, %d springs, %d substeps, N = %d, n_z = %d\n",
              moreau::bench::Describe(fill, index).c_str(), p.anchors, p.springs, p.substeps,
              p.steps, static_cast<int>(disc.problem().network().state_size()));
  Eigen::VectorXd y;
  int iterations = 0;
  Stopwatch clock;  // both attempts (the summary times the last one)
  const double cpu = CpuSeconds();
  const ContinuationSummary summary = mocap::internal::SolveOcpWindowProblem(p, o, y, iterations);
  const double cpu_seconds = CpuSeconds() - cpu;
  Solution ref = FromMoreau(disc, y);
  ref.ok = summary.ok();
  ref.seconds = clock.Seconds();
  const bool retried = !summary.path.empty() && summary.path.front().stiffness_scale < 1.0;
  ref.cpu_seconds = cpu_seconds;
  ref.iterations = iterations;
  // The same positions as the fill's own solve (bit for bit).
  const mocap::internal::OcpWindowResult fill_result =
      mocap::internal::SolveOcpWindow(fill.in, fill.base, fill.network, w, o);
  double same = 0.0;
  for (Eigen::Index k = 0; k < fill_result.positions.rows(); ++k) {
    for (std::size_t j = 0; j < w.free.size(); ++j) {
      const Eigen::Vector3d x =
          p.origin +
          p.scale * ref.states.col(k * p.substeps).segment<3>(6 * static_cast<Eigen::Index>(j));
      same = std::max(
          same,
          (fill_result.positions.block<1, 3>(k, 3 * static_cast<Eigen::Index>(j)).transpose() - x)
              .cwiseAbs()
              .maxCoeff());
    }
  }
  std::printf(
      "# moreau: %s %s (%d Newton solves in it); J %.6e, ||F||_inf %.1e; max |x - "
      "SolveOcpWindow's x| %.1e\n",
      retried ? "retry" : "first attempt", summary.ok() ? "converged" : summary.message.c_str(),
      summary.newton_solves, ref.value, summary.last_newton.final_residual, same);
  PrintLine(p.steps, "moreau fill", ref, ref);
  Eigen::MatrixXd states, rho;
  disc.Unpack(p.warm_start, states, rho);
  // The same relative accuracy as the arm's (value scaled to ≈ 1); unscaled where moreau failed.
  if (!scaling_given) g_obj_scaling = ref.ok ? 1.0 / std::abs(ref.value) : 1.0;
  Ipopt::SmartPtr<bench::TrackingNlp> nlp =
      new bench::TrackingNlp(disc, states, EffectiveControls(disc, p.warm_start));
  const Solution ip = SolveIpopt(nlp, tol, g_window_cpu_seconds);
  if (!ip.ok) std::printf("# ipopt: status %d\n", static_cast<int>(nlp->status()));
  char label[32];
  std::snprintf(label, sizeof label, "ipopt %.0e x%.1e", tol, g_obj_scaling);
  PrintLine(p.steps, label, ip, ref);
  return ref.ok && ip.ok && same == 0.0;
}

int RunWindows(const std::string& recording, double tol, bool scaling_given) {
  mocap::GapFillOptions options;
  options.method = mocap::GapFillMethod::kOcp;
  const moreau::bench::FillWindows fill = moreau::bench::MakeFillWindows(recording, options);
  std::printf("# %s: %d markers, %lld frames at %g Hz; %d gaps in %zu windows (fill defaults)\n",
              recording.c_str(), fill.in.markers(), static_cast<long long>(fill.in.frames()),
              fill.in.rate(), fill.gaps, fill.windows.size());
  std::printf(
      "# differences to moreau's solution: max|dL| over all controls (solver units), |dJ|/|J|, "
      "max|drho|\n");
  std::printf(
      "    N  solver              ok   wall_s    cpu_s  iter  max|dL|   |dJ|/J    "
      "max|drho|\n");
  bool ok = true;
  for (std::size_t w = 0; w < fill.windows.size(); ++w) {
    ok = SolveWindow(fill, w, options.ocp, tol, scaling_given) && ok;
  }
  return ok ? 0 : 1;
}

std::vector<int> ParseSteps(const std::string& list) {
  std::vector<int> steps;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) steps.push_back(std::stoi(item));
  return steps;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> steps = {256, 512, 1024, 2048, 4096};
  double tol = 1e-10;
  bool check = false;
  bool window = false;
  bool scaling_given = false;
  std::string recording = MOREAU_SOURCE_DIR "/../shared/data/mocap/Vicon.c3d";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--check") {
      check = true;
    } else if (arg == "--steps" && i + 1 < argc) {
      steps = ParseSteps(argv[++i]);
    } else if (arg == "--window") {
      window = true;
    } else if (arg == "--ipopt-seconds" && i + 1 < argc) {
      g_window_cpu_seconds = std::stod(argv[++i]);
    } else if (arg == "--recording" && i + 1 < argc) {
      recording = argv[++i];
    } else if (arg == "--obj-scaling" && i + 1 < argc) {
      g_obj_scaling = std::stod(argv[++i]);
      scaling_given = true;
    } else if (arg == "--verbose") {
      g_print_level = 5;
    } else if (arg == "--tol" && i + 1 < argc) {
      tol = std::stod(argv[++i]);
    } else {
      std::fprintf(stderr,
                   "usage: ipopt_bench [--check | --window [--recording FILE] [--ipopt-seconds S]] "
                   "[--steps N,N,...] "
                   "[--tol T] [--obj-scaling S] [--verbose]\n");
      return 2;
    }
  }
  const ArmExample arm;
  const ProblemFamily family = [arm](double p) { return MakeArmProblem(arm, p); };
  if (check) return Check(family);
  if (window) return RunWindows(recording, tol, scaling_given);
  std::printf(
      "# differences to moreau from the documented start: max|dL| over all controls, "
      "|dJ|/|J| of the value, max|drho| over the duals\n");
  std::printf(
      "    N  solver              ok   wall_s    cpu_s  iter  max|dL|   |dJ|/J    "
      "max|drho|\n");
  for (const int n : steps) {
    const PontryaginDiscretization disc(family(1.0), n);
    const Solution documented = SolveMoreau(family, n, moreau::bench::ArmDocumentedStart());
    PrintLine(n, "moreau documented", documented, documented);
    ContinuationOptions direct;
    direct.newton.residual_tolerance = 1e-10;
    PrintLine(n, "moreau direct", SolveMoreau(family, n, direct), documented);
    char label[32];
    std::snprintf(label, sizeof label, "ipopt %.0e x%.0e", tol, g_obj_scaling);
    PrintLine(n, label, SolveIpopt(MakeNlp(disc), tol), documented);
  }
  return 0;
}
