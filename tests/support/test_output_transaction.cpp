// OutputTransaction: all staged outputs land together, or none does (doc/robustness.md).
#include <gtest/gtest.h>

#include "mire/support/atomic_file.hpp"
#include "mire/support/output_transaction.hpp"
#include "test_support.hpp"

#include <fstream>
#include <sstream>

namespace mire::support {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(OutputTransaction, CommitsEveryFileAndFolderTogether) {
  const test::TempDir dir;
  OutputTransaction outputs;
  writeFileAtomically(outputs.stageFile(dir.path() / "a.csv"), "a");
  const fs::path report = outputs.stageFolder(dir.path() / "report");
  writeFileAtomically(report / "r.txt", "r");
  EXPECT_FALSE(fs::exists(dir.path() / "a.csv"));  // nothing visible before the commit
  EXPECT_FALSE(fs::exists(dir.path() / "report"));
  outputs.commit();
  EXPECT_EQ(read(dir.path() / "a.csv"), "a");
  EXPECT_EQ(read(dir.path() / "report/r.txt"), "r");
  EXPECT_EQ(entries(dir.path()), 2u);  // no temporary left
}

TEST(OutputTransaction, WithoutCommitLeavesNothing) {
  const test::TempDir dir;
  {
    OutputTransaction outputs;
    writeFileAtomically(outputs.stageFile(dir.path() / "a.csv"), "a");
    writeFileAtomically(outputs.stageFolder(dir.path() / "report") / "r.txt", "r");
    // an exception here (e.g. the second output failing) skips the commit
  }
  EXPECT_EQ(entries(dir.path()), 0u);
}

TEST(OutputTransaction, MergesIntoAnExistingReportFolderAndKeepsOtherFiles) {
  const test::TempDir dir;
  writeFileAtomically(dir.path() / "report/mine.txt", "mine");
  writeFileAtomically(dir.path() / "report/r.txt", "old");
  OutputTransaction outputs;
  writeFileAtomically(outputs.stageFolder(dir.path() / "report") / "r.txt", "new");
  outputs.commit();
  EXPECT_EQ(read(dir.path() / "report/r.txt"), "new");
  EXPECT_EQ(read(dir.path() / "report/mine.txt"), "mine");
  EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(OutputTransaction, ReplacesAWholeFolderWhenAsked) {
  const test::TempDir dir;
  writeFileAtomically(dir.path() / "sim/images/old.png", "old");
  OutputTransaction outputs;
  const fs::path staged = outputs.stageFolder(dir.path() / "sim", OutputTransaction::FolderCommit::ReplaceWhole);
  writeFileAtomically(staged / "images/new.png", "new");
  outputs.commit();
  EXPECT_FALSE(fs::exists(dir.path() / "sim/images/old.png"));
  EXPECT_EQ(read(dir.path() / "sim/images/new.png"), "new");
  EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(OutputTransaction, RefusesToCommitWhatWasNotWritten) {
  const test::TempDir dir;
  OutputTransaction outputs;
  writeFileAtomically(outputs.stageFile(dir.path() / "a.csv"), "a");
  (void)outputs.stageFile(dir.path() / "b.csv");  // never written
  EXPECT_THROW(outputs.commit(), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir.path() / "a.csv"));
}

}  // namespace
}  // namespace mire::support
