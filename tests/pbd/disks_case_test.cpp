// The disks case of paper 000, section 4.3: feasibility, convergence to a PNGS reference, the
// bounded-violation property d_S(Φ_h(x)) < K h (Definition 2.8), and neighbour-list exactness.
#include <gtest/gtest.h>

#include <cmath>

#include "moreau/common/error.h"
#include "moreau/pbd/cases.h"
#include "moreau/pbd/study.h"

namespace moreau::pbd {
namespace {

StudyProblem DisksProblem(const DisksCase& c, PairSearch search = PairSearch::kVerletList) {
  StudyProblem p;
  p.constraints = std::make_shared<ParticleSystemModel>(
      std::make_shared<const particles::ParticleModel>(c.MakeModel()),
      ParticleConstraintsOptions{search, 1.0});
  p.drift = c.MakeDrift();
  p.x0 = c.InitialState();
  p.T = c.T;
  return p;
}

TEST(DisksCase, InitialStateIsFeasibleAndReproducible) {
  DisksCase c;
  c.wall = -0.5;
  const Vector a = c.InitialState();
  const Vector b = c.InitialState();
  EXPECT_EQ(a, b);  // same seed, same bits
  ParticleConstraints pc(c.MakeModel(), {PairSearch::kAllPairs, 1.0});
  EXPECT_LE(pc.MaxViolation(a), 0.0);
  c.seed = 2;
  EXPECT_NE(c.InitialState(), a);
  c.count = 10000;  // cannot fit in the box
  c.box = 1.0;
  EXPECT_THROW(c.InitialState(), InputError);
}

TEST(DisksCase, VerletListGivesTheSameBitsAsAllPairs) {
  DisksCase c;
  c.wall = -0.6;
  c.T = 2.0;
  for (Method m : {Method::kPBD, Method::kPNGS}) {
    StepperOptions o;
    o.method = m;
    o.h = 1.0 / 512;
    Vector xa, xv;
    auto all = DisksProblem(c, PairSearch::kAllPairs).constraints->MakeWorkspace();
    auto verlet = DisksProblem(c, PairSearch::kVerletList).constraints->MakeWorkspace();
    const auto sa = Simulate(*c.MakeDrift(), *all, o, c.InitialState(), c.T, {}, &xa);
    const auto sv = Simulate(*c.MakeDrift(), *verlet, o, c.InitialState(), c.T, {}, &xv);
    EXPECT_EQ(xa, xv) << MethodName(m);
    EXPECT_EQ(sa.counters.constraint_evaluations, sv.counters.constraint_evaluations);
    EXPECT_EQ(sa.max_violation, sv.max_violation);
    EXPECT_GT(dynamic_cast<ParticleConstraints&>(*verlet).neighbour_stats().neighbour_list_builds, 1);
  }
}

TEST(DisksCase, ParticleKernelsMatchTheGenericSetList) {
  // The same sets in the same order as ConstraintSet objects: agreement to round-off.
  DisksCase c;
  c.count = 15;
  c.wall = -0.4;
  c.T = 1.0;
  const particles::ParticleModel model = c.MakeModel();
  ConstraintSetList list(2 * c.count);
  for (int i = 0; i < c.count; ++i) {
    for (int j = i + 1; j < c.count; ++j) {
      list.Add(std::make_unique<PairNonOverlap>(2 * c.count, 2, i, j, 2 * c.radius));
    }
  }
  for (int i = 0; i < c.count; ++i) {
    Vector n = Vector::Zero(2 * c.count);
    n[2 * i + 1] = 1.0;
    list.Add(std::make_unique<HalfSpace>(n, *c.wall + c.radius));
  }
  ParticleConstraints particles(model, {PairSearch::kAllPairs, 1.0});
  ASSERT_EQ(list.num_sets(), particles.num_sets());
  for (Method m : {Method::kPBD, Method::kPGS, Method::kPenalty}) {
    StepperOptions o;
    o.method = m;
    o.h = 1.0 / 256;
    Vector x_list, x_particles;
    Simulate(*c.MakeDrift(), list, o, c.InitialState(), c.T, {}, &x_list);
    Simulate(*c.MakeDrift(), particles, o, c.InitialState(), c.T, {}, &x_particles);
    EXPECT_LE((x_list - x_particles).lpNorm<Eigen::Infinity>(), 1e-12) << MethodName(m);
  }
}

TEST(DisksCase, PbdViolationIsBoundedByKh) {
  // Definition 2.8 (bounded constraint violation): after every PBD step the largest overlap is
  // below K h. For the paper's setting (N = 40, R = 0.1, γ = 1) we measure max overlap / h ≤ 3.6
  // for h = 2^−3 … 2^−14 and state K = 4. Checked over all pairs, not only the neighbour list.
  const DisksCase c{40, 0.1, 1.0, 1.0, 1, std::nullopt, 0.0};
  constexpr double kK = 4.0;
  for (int k = 3; k <= 14; ++k) {
    const double h = std::pow(2.0, -k);
    StepperOptions o;
    o.h = h;
    o.monitor_violation = false;
    auto constraints = DisksProblem(c).constraints->MakeWorkspace();
    const auto& pc = dynamic_cast<ParticleConstraints&>(*constraints);
    double worst = 0.0;
    Simulate(*c.MakeDrift(), *constraints, o, c.InitialState(), c.T,
             [&](std::int64_t, double, ConstVectorRef x) {
               worst = std::max(worst, pc.MaxPairOverlapAllPairs(x));
               return true;
             });
    EXPECT_LT(worst, kK * h) << "h = 2^-" << k;
    EXPECT_GT(worst, 0.0);  // contacts do happen
  }
}

// PBD at h = 2^−first … 2^−last against a PNGS reference with h = 2^−reference_exponent
// (reltol 1e−10, abstol 1e−12); the rows of the study.
std::vector<StudyRow> PbdAgainstPngsReference(const DisksCase& c, int reference_exponent,
                                              int first, int last) {
  StudyProblem problem = DisksProblem(c);
  StepperOptions ref;
  ref.method = Method::kPNGS;
  ref.h = std::pow(2.0, -reference_exponent);
  ref.monitor_violation = false;
  auto reference = std::make_shared<SampledTrajectory>(
      ComputeReference(problem, ref, std::pow(2.0, -last)));
  problem.solution = [reference](double t) { return reference->At(t); };
  std::vector<double> hs;
  for (int k = first; k <= last; ++k) hs.push_back(std::pow(2.0, -k));
  return RunStudy(problem, {ParseMethodSpec("pbd")}, hs, StepperOptions{});
}

double OrderOf(const std::vector<StudyRow>& rows) {
  std::vector<double> h, e;
  for (const StudyRow& r : rows) {
    h.push_back(r.h);
    e.push_back(r.error);
  }
  return ObservedOrder(h, e);
}

TEST(DisksCase, PbdConvergesToThePngsReferenceSlow) {
  // The paper's setting. Reference h = 2^−19 (the paper used 1e−6; this one runs in about
  // 12 s); PBD over h = 2^−12 … 2^−15, the asymptotic range.
  const DisksCase c{40, 0.1, 1.0, 1.0, 1, std::nullopt, 0.0};
  const auto rows = PbdAgainstPngsReference(c, 19, 12, 15);
  EXPECT_NEAR(OrderOf(rows), 1.0, 0.15);
  EXPECT_LT(rows.back().error, 2e-3);
}

TEST(DisksCase, ConvergesOnASmallCase) {
  // A cheap version of the reference test that also runs under the sanitizers: 10 disks above a
  // wall, T = 0.5.
  const DisksCase c{10, 0.15, 1.0, 0.5, 3, -0.6, 0.8};
  const auto rows = PbdAgainstPngsReference(c, 16, 9, 12);
  for (const StudyRow& r : rows) EXPECT_LT(r.max_violation, 4.0 * r.h);
  EXPECT_NEAR(OrderOf(rows), 1.0, 0.15);
}

}  // namespace
}  // namespace moreau::pbd
