// `mire check-mechanism` (doc/mechanisms.md, "Checking a description"): every shipped
// description and built-in model passes with the rank the identification finds; descriptions
// that cannot work are refused with the leg or the pose at fault.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "test_support.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;

fs::path example(const std::string& name) { return test::sourceDir() / "examples" / "mechanisms" / (name + ".yaml"); }

// `text` with every `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

struct Expected {
  std::string mechanism;
  int rank, geometric;
};

TEST(CheckMechanismCli, ShippedDescriptionsAndBuiltInModelsAreUsableWithTheirRank) {
  // The ranks are those of IdentificationRecoversPerturbedTruthWithTheGaugeFromTheData
  // (tests/mechanism/test_described.cpp) and doc/mechanisms.md.
  const std::vector<Expected> cases = {{example("linear-delta").string(), 21, 33},
                                       {example("6-rus").string(), 66, 78},
                                       {example("6-pus").string(), 54, 60},
                                       {example("delta").string(), 24, 39},
                                       {example("gough-stewart").string(), 42, 42},
                                       {"delta", 14, 8},
                                       {"gough-stewart", 42, 42}};
  for (const Expected& c : cases) {
    SCOPED_TRACE(c.mechanism);
    test::TempDir dir;
    ASSERT_EQ(test::runMireIn(dir, "check-mechanism " + c.mechanism), 0) << test::readText(dir.path() / "stderr.txt");
    const std::string out = test::readText(dir.path() / "stdout.txt");
    EXPECT_NE(out.find("verdict: usable"), std::string::npos) << out;
    EXPECT_NE(out.find("parameters: " + std::to_string(c.geometric) + " geometric"), std::string::npos) << out;
    EXPECT_NE(out.find("expected identifiable rank " + std::to_string(c.rank) + " "), std::string::npos) << out;
    EXPECT_NE(out.find("gauge (held"), std::string::npos) << out;
  }
}

// (description text, what the error must say)
void expectRefused(const std::string& description, const std::string& message) {
  test::TempDir dir;
  const fs::path file = dir.path() / "robot.yaml";
  test::writeText(file, description);
  EXPECT_EQ(test::runMireIn(dir, "check-mechanism " + file.string()), 1) << test::readText(dir.path() / "stdout.txt");
  const std::string err = test::readText(dir.path() / "stderr.txt");
  EXPECT_NE(err.find(message), std::string::npos) << err;
  EXPECT_NE(test::readText(dir.path() / "stdout.txt").find("verdict: not usable"), std::string::npos);
}

TEST(CheckMechanismCli, RodsTooShortForTheHomeAreNamedLegByLeg) {
  expectRefused(replaced(test::readText(example("linear-delta")), "rod: 0.25", "rod: 0.10"),
                "the home pose does not assemble: leg(s) 1, 2, 3");
}

TEST(CheckMechanismCli, AHomeAtTheEdgeOfTheLegsReachIsRefused) {
  // Rods barely longer than the 0.16 m from rail to effector joint: they lie flat at home.
  expectRefused(replaced(test::readText(example("linear-delta")), "rod: 0.25", "rod: 0.1601"),
                "at the edge of the reach of leg(s) 1, 2, 3");
}

TEST(CheckMechanismCli, OneLegThatCannotReachIsNamedAlone) {
  const std::string text = test::readText(example("6-rus"));
  const std::size_t first = text.find("rod: 0.25");
  std::string broken = text;
  broken.replace(broken.find("rod: 0.25", first + 1), 9, "rod: 0.05");
  expectRefused(broken, "leg(s) 2 have no solution");
}

TEST(CheckMechanismCli, ParallelLegsAreASingularHome) {
  // Every leg vertical (platform joints above the base joints): the platform can turn about z
  // and slide sideways without any leg changing length.
  std::string text = test::readText(example("gough-stewart"));
  const std::regex base("base: (\\[[^\\]]*\\])\\n    platform: \\[[^\\]]*\\]");
  text = std::regex_replace(text, base, "base: $1\n    platform: $1");
  expectRefused(text, "a singularity of the platform");
}

TEST(CheckMechanismCli, AnUnreadableDescriptionNamesTheFileAndLine) {
  test::TempDir dir;
  const fs::path file = dir.path() / "robot.yaml";
  test::writeText(file, replaced(test::readText(example("6-pus")), "axis: [0, 0, 1]", "axis: [0, 1]"));
  EXPECT_EQ(test::runMireIn(dir, "check-mechanism " + file.string()), 1);
  const std::string err = test::readText(dir.path() / "stderr.txt");
  EXPECT_NE(err.find("robot.yaml:"), std::string::npos) << err;
  EXPECT_NE(err.find("expected 3 numbers"), std::string::npos) << err;
}

}  // namespace
}  // namespace mire::app
