// The shared summary vocabulary: termination names and the JSON every summary starts from.
#include "moreau/common/summary_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "moreau/common/error.h"
#include "moreau/common/termination.h"

namespace moreau {
namespace {

TEST(Termination, NamesRoundTripAndOnlyCompletedOrConvergedSucceed) {
  for (Termination t :
       {Termination::kCompleted, Termination::kConverged, Termination::kMaxIterations,
        Termination::kLineSearchFailed, Termination::kSingularJacobian, Termination::kDiverged,
        Termination::kNonFinite, Termination::kInterrupted}) {
    EXPECT_EQ(ParseTermination(ToString(t)), t);
    EXPECT_EQ(IsSuccess(t), t == Termination::kCompleted || t == Termination::kConverged);
  }
  EXPECT_THROW(ParseTermination("finished"), InputError);
}

TEST(SummaryJson, HoldsTheSharedKeys) {
  const nlohmann::json j = SummaryJson(Termination::kDiverged, "residual 1e13", 1.5);
  EXPECT_EQ(j.at("termination"), "diverged");
  EXPECT_EQ(j.at("ok"), false);
  EXPECT_EQ(j.at("message"), "residual 1e13");
  EXPECT_EQ(j.at("total_seconds"), 1.5);
}

TEST(SummaryJson, NonFiniteNumbersBecomeNull) {
  EXPECT_TRUE(FiniteOrNull(std::nan("")).is_null());
  EXPECT_TRUE(FiniteOrNull(std::numeric_limits<double>::infinity()).is_null());
  EXPECT_EQ(FiniteOrNull(2.5), 2.5);
}

}  // namespace
}  // namespace moreau
