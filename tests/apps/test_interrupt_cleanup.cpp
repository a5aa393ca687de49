// SIGINT during `mire simulate`: the run stops with 128 + SIGINT and leaves neither its
// temporary folder nor a half-written dataset (doc/robustness.md).
#include <gtest/gtest.h>

#include "test_support.hpp"

#include <fstream>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

// Interrupts one `mire simulate calibration` `delay` after its temporary folder appeared and
// checks the exit code and that only the inputs remain.
void interruptSimulateAfter(const std::string& delay) {
  SCOPED_TRACE("SIGINT " + delay + " s after the temporary folder appeared");
  const test::TempDir dir;
  const fs::path specs = test::sourceDir() / "datasets/specs";
  fs::copy(specs / "reference_camera.yaml", dir.path() / "camera.yaml");
  fs::copy(specs / "target_chessboard.yaml", dir.path() / "target.yaml");
  {
    std::ofstream spec(dir.path() / "spec.yaml");
    spec << "%YAML:1.0\n---\ncamera: \"camera.yaml\"\ntarget: \"target.yaml\"\ncalibration:\n  views: 200\n";
  }
  // Start, wait until the temporary output folder exists (the interrupt handler is installed
  // by then), interrupt, report the exit code. A busy machine may be slow to get there: wait up
  // to 120 s, and never hang — without the folder, or when the interrupt does not end mire
  // within 60 s, the process is killed and the code file says so.
  const std::string d = dir.path().string();
  const std::string script = "cd " + d + " && { " + test::mireBinary().string() +
                             " simulate calibration --spec spec.yaml -o out >/dev/null 2>&1 & pid=$!; "
                             "for i in $(seq 2400); do ls -a | grep -q ^.tmp-dir- && break; sleep 0.05; done; "
                             "if ! ls -a | grep -q ^.tmp-dir-; then kill -KILL $pid; wait $pid; echo 1001 > code; "
                             "else sleep " +
                             delay +
                             "; kill -INT $pid; (sleep 60; kill -KILL $pid) >/dev/null 2>&1 & watchdog=$!; "
                             "wait $pid; echo $? > code; kill $watchdog 2>/dev/null; fi; }";
  EXPECT_EQ(test::runCommand("sh -c '" + script + "'"), 0);
  std::ifstream code_file(dir.path() / "code");
  int code = -1;
  code_file >> code;
  EXPECT_NE(code, 1001) << "mire simulate made no temporary output folder within 120 s";
  EXPECT_NE(code, 128 + 9) << "mire simulate did not end within 60 s of SIGINT";
  EXPECT_EQ(code, 128 + 2);
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name == "camera.yaml" || name == "target.yaml" || name == "spec.yaml" || name == "code") << name;
  }
}

// Several moments: the workers write images in parallel, and an interrupt in the middle of a
// write once left a file in the removed folder (and a handler calling opendir deadlocked).
TEST(InterruptCleanup, SigintDuringSimulateLeavesNothing) {
  for (const char* delay : {"0.1", "0.35", "0.6", "0.85", "1.1"}) interruptSimulateAfter(delay);
}

}  // namespace
}  // namespace mire::app
