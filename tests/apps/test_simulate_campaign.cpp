// `mire simulate campaign` (doc/simulation.md): a rendered Delta campaign on disk, then the commands it
// prints run as a user would (calibrate -> measure -> identify), the identified parameters
// scored against the campaign's truth/; and the output folder's rules.
#include "test_support.hpp"

#include "mire/mechanism/io.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// Runs `mire <args>` in `folder`; returns its exit code, stdout+stderr in *output.
int mireIn(const fs::path& folder, const std::string& args, std::string* output) {
  int code = -1;
  *output = mire::test::captureCommand(
      "cd '" + folder.string() + "' && " + mire::test::mireBinary().string() + " " + args + " </dev/null", &code);
  return code;
}

// The commands the campaign's summary tells the user to run next ("  mire ..." lines).
std::vector<std::string> printedCommands(const std::string& output) {
  std::vector<std::string> commands;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("  mire ", 0) == 0) commands.push_back(line.substr(7));
  return commands;
}

double number(const mire::mechanism::ParameterFile& file, const std::string& key) {
  const auto* entry = file.find(key);
  if (entry == nullptr) throw std::runtime_error(file.path.string() + ": no " + key);
  return file.number(*entry);
}

// The campaign's ISO 9283 test read by the printed `mire accuracy` (through truth/iso9283.yaml):
// the standard's 5 positions x 30 cycles, the nominal controller's error resolved (AP_p well above
// its σ and above the camera's noise-only figure).
void expectIsoTest(const fs::path& accuracy_json) {
  const auto json = nlohmann::json::parse(mire::test::readText(accuracy_json));
  EXPECT_EQ(json["cycles_used"], 150);
  ASSERT_EQ(json["positions"].size(), 5u);
  for (const auto& p : json["positions"]) {
    EXPECT_EQ(p["cycles"], 30);
    const double ap = p["AP_p_m"], sigma = p["sigma_AP_p_m"];
    std::printf("%s: AP_p %.3f mm, sigma %.3f mm\n", p["position"].get<std::string>().c_str(), ap * 1e3, sigma * 1e3);
    EXPECT_GT(ap, 10 * sigma);
    EXPECT_LT(sigma, 0.1e-3);
  }
}

double meanAp(const fs::path& accuracy_json) {
  const auto json = nlohmann::json::parse(mire::test::readText(accuracy_json));
  double sum = 0.0;
  for (const auto& p : json["positions"]) sum += p["AP_p_m"].get<double>();
  return sum / static_cast<double>(json["positions"].size());
}

// `mire simulate iso9283` then `mire accuracy`, as printed: the same robot driven by the identified
// model's commands, read through the identified file; the mean AP_p falls below `ratio` × before.
void expectCompensated(const fs::path& before_json, const fs::path& after_json, double ratio) {
  const double before = meanAp(before_json), after = meanAp(after_json);
  std::printf("ISO 9283 mean AP_p: nominal controller %.3f mm, identified model's commands %.3f mm\n", before * 1e3,
              after * 1e3);
  EXPECT_LT(after, ratio * before);
}

}  // namespace

// The fastest mechanism (27 poses), one image per pose, 6 calibration views: about 3 s in all.
TEST(SimulateCampaign, DeltaByHandIdentifiesTheTrueLengths) {
  const mire::test::TempDir dir;
  std::string output;
  ASSERT_EQ(mireIn(dir.path(),
                   "simulate campaign --mechanism delta -o campaign --images-per-pose 1 --calibration-views 6", &output),
            0)
      << output;
  for (const char* file : {"target.yaml", "joints.csv", "lines.csv", "calibration/images/view_005.png",
                           "poses/p027/img_00.png", "truth/robot.yaml", "truth/delta-legs.yaml"})
    EXPECT_TRUE(fs::exists(dir.path() / "campaign" / file)) << file;
  EXPECT_FALSE(fs::exists(dir.path() / "campaign/poses/p001/img_01.png"));

  // The printed chain, exactly as printed, from the folder the campaign was made in.
  const std::vector<std::string> commands = printedCommands(output);
  ASSERT_EQ(commands.size(), 6u) << output;
  EXPECT_EQ(commands[0].rfind("calibrate ", 0), 0u);
  EXPECT_EQ(commands[1].rfind("measure ", 0), 0u);
  EXPECT_NE(commands[2].find("--model delta-legs"), std::string::npos) << commands[2];
  EXPECT_EQ(commands[3].rfind("accuracy ", 0), 0u);
  EXPECT_EQ(commands[4].rfind("simulate iso9283 --mechanism delta --seed 2004 ", 0), 0u) << commands[4];
  for (const std::string& command : commands) ASSERT_EQ(mireIn(dir.path(), command, &output), 0) << command << output;
  expectIsoTest(dir.path() / "accuracy.json");
  expectCompensated(dir.path() / "accuracy.json", dir.path() / "accuracy_after.json", 0.1);

  // The lengths do not depend on the frame the gauge defines: compared with the truth directly.
  // Measured (seed 2004): |error| <= 0.48 mm, |error/σ| <= 2.4 (RMS 1.3); the other parameters
  // are in the gauge's frame, RMS error/σ over all 24 against the raw truth 2.6.
  const auto identified = mire::mechanism::readParameterFile(dir.path() / "identified.yaml");
  const auto truth = mire::mechanism::readParameterFile(dir.path() / "campaign/truth/delta-legs.yaml");
  for (const std::string leg : {"1", "2", "3"})
    for (const std::string length : {"L", "l"}) {
      const std::string name = length + leg;
      const double error = number(identified, name) - number(truth, name);
      const double sigma = number(identified, "sigma_" + name);
      EXPECT_LT(std::abs(error), 1.5e-3) << name;
      EXPECT_LT(std::abs(error / sigma), 5.0) << name << " error " << error << " m, sigma " << sigma << " m";
      EXPECT_GT(sigma, 0.05e-3) << name;  // σ is not absurdly small (measured 0.18–1.0 mm)
    }
  double sum = 0.0;
  int count = 0;
  for (const auto& entry : truth.entries) {
    if (entry.key == "model" || entry.key == "created_by") continue;
    const double z = (number(identified, entry.key) - truth.number(entry)) / number(identified, "sigma_" + entry.key);
    sum += z * z;
    ++count;
  }
  ASSERT_EQ(count, 24);
  EXPECT_LT(std::sqrt(sum / count), 5.0);
}

// A robot of the user's own (a described linear delta, 27 poses): the campaign is rendered from
// the description, its printed chain identifies it from the same file, and the rods and encoder
// gains, which no gauge moves, match the truth despite the bent encoders no description holds.
TEST(SimulateCampaign, DescribedRobotByHandIdentifiesItsRodsAndGains) {
  const mire::test::TempDir dir;
  const fs::path description = mire::test::sourceDir() / "examples" / "mechanisms" / "linear-delta.yaml";
  std::string output;
  ASSERT_EQ(mireIn(dir.path(),
                   "simulate campaign --model " + description.string() +
                       " -o campaign --images-per-pose 1 --calibration-views 6",
                   &output),
            0)
      << output;
  for (const char* file : {"joints.csv", "lines.csv", "poses/p027/img_00.png", "truth/robot.yaml",
                           "truth/robot_geometry.yaml", "truth/robot_geometry_mechanism.yaml"})
    EXPECT_TRUE(fs::exists(dir.path() / "campaign" / file)) << file;
  EXPECT_NE(mire::test::readText(dir.path() / "campaign/joints.csv").find("q1_m"), std::string::npos);
  EXPECT_NE(mire::test::readText(dir.path() / "campaign/truth/robot.yaml").find("encoder_curvature"), std::string::npos);
  const std::vector<std::string> commands = printedCommands(output);
  ASSERT_EQ(commands.size(), 6u) << output;
  EXPECT_NE(commands[2].find("--model " + description.string()), std::string::npos) << commands[2];
  EXPECT_NE(commands[4].find("--model " + description.string()), std::string::npos) << commands[4];
  for (const std::string& command : commands) ASSERT_EQ(mireIn(dir.path(), command, &output), 0) << command << output;
  expectIsoTest(dir.path() / "accuracy.json");
  expectCompensated(dir.path() / "accuracy.json", dir.path() / "accuracy_after.json", 0.5);

  const auto identified = mire::mechanism::readParameterFile(dir.path() / "identified.yaml");
  const auto truth = mire::mechanism::readParameterFile(dir.path() / "campaign/truth/robot_geometry.yaml");
  for (const std::string leg : {"1", "2", "3"})
    for (const std::string& name : {"l" + leg, "g" + leg}) {
      const double error = number(identified, name) - number(truth, name);
      const double sigma = number(identified, "sigma_" + name);
      std::printf("%s: error %.3g, sigma %.3g\n", name.c_str(), error, sigma);
      EXPECT_LT(std::abs(error / sigma), 4.0) << name << " error " << error << ", sigma " << sigma;
    }
}

TEST(SimulateCampaign, RefusesAForeignFolderReplacesAPreviousCampaign) {
  const mire::test::TempDir dir;
  const fs::path mine = dir.path() / "mine";
  fs::create_directories(mine);
  mire::test::writeText(mine / "notes.txt", "my notes");
  std::string output;
  EXPECT_EQ(mireIn(dir.path(), "simulate campaign --mechanism delta -o mine --images-per-pose 1", &output), 2);
  EXPECT_NE(output.find("not a previous campaign"), std::string::npos) << output;
  EXPECT_EQ(mire::test::readText(mine / "notes.txt"), "my notes");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);  // no temporary

  // A previous campaign holding a file mire does not write (a user's notes, at the top or
  // inside poses/) is refused before any rendering: a rerun never deletes what it did not write.
  const fs::path previous = dir.path() / "previous";
  fs::create_directories(previous / "truth");
  fs::create_directories(previous / "poses/p001");
  fs::create_directories(previous / "calibration/images");
  mire::test::writeText(previous / "truth/robot.yaml", "model: delta-legs\n");
  mire::test::writeText(previous / "poses/p001/notes.txt", "my notes");
  mire::test::writeText(previous / "calibration/images/view_099.png", "an older run's extra view");
  const std::string rerun =
      "simulate campaign --mechanism delta -o previous --images-per-pose 1 --calibration-views 3 --seed 7";
  EXPECT_EQ(mireIn(dir.path(), rerun, &output), 2);
  EXPECT_NE(output.find("poses/p001/notes.txt"), std::string::npos) << output;
  EXPECT_EQ(mire::test::readText(previous / "poses/p001/notes.txt"), "my notes");
  // Without it, the previous campaign is replaced whole (the older run's extra view goes).
  fs::remove(previous / "poses/p001/notes.txt");
  ASSERT_EQ(mireIn(dir.path(), rerun, &output), 0) << output;
  EXPECT_FALSE(fs::exists(previous / "calibration/images/view_099.png"));
  EXPECT_TRUE(fs::exists(previous / "poses/p027/img_00.png"));
  EXPECT_NE(mire::test::readText(previous / "truth/robot.yaml").find("geometry:"), std::string::npos);
  EXPECT_NE(output.find("(seed 7)"), std::string::npos) << output;
}
