#pragma once
// A strict CSV reader for mire's numeric tables (poses.csv, joints.csv, ...): every error
// names the file, the line and the column.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace mire::support {

struct CsvTable {
  std::filesystem::path path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::size_t> line_numbers;  // 1-based line of each row in the file

  // Index of a header column; throws naming the file if it is missing.
  std::size_t column(const std::string& name) const;
  // Cell as a finite double; throws "file:line: column 'name': ..." otherwise.
  double number(std::size_t row, std::size_t column) const;
  // Location "file:line" of a row, for messages.
  std::string where(std::size_t row) const;
};

// Reads a comma-separated file with a header line. Blank lines and lines starting with '#'
// are skipped. Throws std::runtime_error naming the file and line on a malformed row.
CsvTable readCsv(const std::filesystem::path& path);

// Formats a double with enough digits to round-trip (for CSV output).
std::string formatNumber(double value, int significant_digits = 17);

}  // namespace mire::support
