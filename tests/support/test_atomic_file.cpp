#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"
#include "test_support.hpp"

#include <fstream>

TEST(AtomicFile, ReplacesContentsAndLeavesNoTemporary) {
  mire::test::TempDir dir;
  const auto path = dir.path() / "out.txt";
  mire::support::writeFileAtomically(path, "first");
  mire::support::writeFileAtomically(path, "second");
  EXPECT_EQ(mire::test::readText(path), "second");
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST(AtomicFile, FailingWriterKeepsPreviousFile) {
  mire::test::TempDir dir;
  const auto path = dir.path() / "out.txt";
  mire::support::writeFileAtomically(path, "kept");
  EXPECT_THROW(mire::support::writeAtomically(path, [](const std::filesystem::path&) { return false; }),
               std::runtime_error);
  EXPECT_EQ(mire::test::readText(path), "kept");
}

TEST(Csv, ReportsFileLineAndColumn) {
  mire::test::TempDir dir;
  const auto path = dir.path() / "t.csv";
  mire::support::writeFileAtomically(path, "a,b\n1,2\n# comment\n3,x\n");
  const auto table = mire::support::readCsv(path);
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_DOUBLE_EQ(table.number(0, table.column("b")), 2.0);
  try {
    table.number(1, 1);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("t.csv:4: column 'b'"), std::string::npos) << e.what();
  }
  mire::support::writeFileAtomically(path, "a,b\n1,2,3\n");
  EXPECT_THROW(mire::support::readCsv(path), std::runtime_error);
}

TEST(Csv, NonFiniteValuesAreRejected) {
  mire::test::TempDir dir;
  const auto path = dir.path() / "t.csv";
  mire::support::writeFileAtomically(path, "a\nnan\n");
  const auto table = mire::support::readCsv(path);
  EXPECT_THROW(table.number(0, 0), std::runtime_error);
}
