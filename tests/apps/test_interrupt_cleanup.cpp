// SIGINT during `mire simulate`: the run stops with 128 + SIGINT and leaves neither its
// temporary folder nor a half-written dataset (doc/robustness.md).
#include <gtest/gtest.h>

#include "test_support.hpp"

#include <fstream>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

TEST(InterruptCleanup, SigintDuringSimulateLeavesNothing) {
  const test::TempDir dir;
  const fs::path specs = test::sourceDir() / "datasets/specs";
  fs::copy(specs / "reference_camera.yaml", dir.path() / "camera.yaml");
  fs::copy(specs / "target_chessboard.yaml", dir.path() / "target.yaml");
  {
    std::ofstream spec(dir.path() / "spec.yaml");
    spec << "%YAML:1.0\n---\ncamera: \"camera.yaml\"\ntarget: \"target.yaml\"\ncalibration:\n  views: 200\n";
  }
  // Start, wait until the temporary output folder exists, interrupt, report the exit code.
  const std::string d = dir.path().string();
  const std::string script = "cd " + d + " && { " + test::mireBinary().string() +
                             " simulate calibration --spec spec.yaml -o out >/dev/null 2>&1 & pid=$!; "
                             "for i in $(seq 600); do ls -a | grep -q ^.tmp-dir- && break; sleep 0.05; done; "
                             "sleep 0.5; kill -INT $pid; wait $pid; echo $? > code; }";
  ASSERT_EQ(test::runCommand("sh -c '" + script + "'"), 0);
  std::ifstream code_file(dir.path() / "code");
  int code = -1;
  code_file >> code;
  EXPECT_EQ(code, 128 + 2);
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name == "camera.yaml" || name == "target.yaml" || name == "spec.yaml" || name == "code") << name;
  }
}

}  // namespace
}  // namespace mire::app
