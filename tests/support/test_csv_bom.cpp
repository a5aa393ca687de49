// A UTF-8 byte-order mark (Excel's "CSV UTF-8") is not part of the first column's name.
#include <gtest/gtest.h>

#include "mire/support/csv.hpp"
#include "test_support.hpp"

#include <fstream>

namespace mire::support {
namespace {

TEST(CsvBom, ByteOrderMarkIsDropped) {
  const test::TempDir dir;
  const auto path = dir.path() / "poses.csv";
  std::ofstream(path) << "\xEF\xBB\xBFpose_id,tx_m\r\n1,0.5\r\n";
  const CsvTable table = readCsv(path);
  EXPECT_EQ(table.column("pose_id"), 0u);
  EXPECT_DOUBLE_EQ(table.number(0, table.column("tx_m")), 0.5);
}

TEST(CsvBom, ByteOrderMarkElsewhereIsNotDropped) {
  const test::TempDir dir;
  const auto path = dir.path() / "poses.csv";
  std::ofstream(path) << "pose_id,tx_m\n\xEF\xBB\xBF"
                         "1,0.5\n";
  const CsvTable table = readCsv(path);
  EXPECT_EQ(table.rows.at(0).at(0),
            "\xEF\xBB\xBF"
            "1");
}

}  // namespace
}  // namespace mire::support
