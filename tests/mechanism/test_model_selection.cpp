// Model selection (doc/plan-and-select.md): on simulated H4 campaigns the one-SE rule
// recommends a model-12 variant when the robot is model 12, a model-31 variant when its legs
// differ; the --models parser and its errors.
#include <gtest/gtest.h>

#include "h4_selection_campaign.hpp"
#include "mire/mechanism/model_selection.hpp"

namespace mire::mechanism {
namespace {

std::vector<SelectionCandidate> h4Candidates(const std::string& text = "h4-12:A,B,C,D,h4-31c:E,F,G,H") {
  return parseSelectionCandidates(text, [](const std::string& n) { return makeDesignModel(n); });
}

TEST(ModelSelection, ParsesVariantsAndModels) {
  const auto c = h4Candidates();
  ASSERT_EQ(c.size(), 8u);
  EXPECT_EQ(c[0].label, "A");
  EXPECT_EQ(c[0].model.registered.name, "h4-12");
  EXPECT_EQ(c[7].label, "H");
  EXPECT_EQ(c[7].model.registered.name, "h4-31c");
  const auto d = h4Candidates("delta,delta-legs");
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[1].label, "delta-legs");
  EXPECT_THROW(h4Candidates("h4-12:E"), std::invalid_argument);  // E is a model-31 variant
  EXPECT_THROW(h4Candidates("delta:A"), std::invalid_argument);
  EXPECT_THROW(h4Candidates("h4-99"), std::invalid_argument);  // unknown model
  EXPECT_THROW(h4Candidates("A,B"), std::invalid_argument);    // letters without a model
  EXPECT_EQ(defaultSelectionModels(4, Unit::Radian), "h4-12:A,B,C,D,h4-31c:E,F,G,H");
  EXPECT_EQ(defaultSelectionModels(6, Unit::Metre), "gough-stewart,gough-stewart-gains");
}

TEST(ModelSelection, ExactModel12RobotGetsAModel12Variant) {
  const SelectionResult r = selectModel(h4Candidates("h4-12:B,C,D,h4-31c:G,H"), test::h4SelectionCampaign(100, false));
  ASSERT_GE(r.recommended, 0);
  const std::string rec = r.recommendedLabel();
  EXPECT_TRUE(rec == "B" || rec == "C" || rec == "D") << rec;
  for (const ModelScore& s : r.scores) {
    EXPECT_TRUE(s.ok) << s.label << ": " << s.message;
    EXPECT_GT(s.cv_se, 0.0);
    EXPECT_GE(s.cv_rms(), 0.8 * s.fit_rms) << s.label;  // held-out residuals are not smaller than fitted ones
  }
  EXPECT_FALSE(r.tests.empty());
}

TEST(ModelSelection, LegsThatDifferGetAModel31Variant) {
  const SelectionResult r = selectModel(h4Candidates("h4-12:C,D,h4-31c:G,H"), test::h4SelectionCampaign(101, true));
  const std::string rec = r.recommendedLabel();
  EXPECT_TRUE(rec == "G" || rec == "H") << rec;
  // The F-test of D within G/H rejects model 12.
  bool rejected = false;
  for (const NestedTest& t : r.tests)
    if (r.scores[static_cast<std::size_t>(t.simpler)].label == "D") rejected = t.p_value < 1e-3;
  EXPECT_TRUE(rejected);
}

}  // namespace
}  // namespace mire::mechanism
