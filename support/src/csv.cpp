#include "mire/support/csv.hpp"

#include "mire/support/input_file.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mire::support {

namespace {
std::string trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return {};
  const auto end = s.find_last_not_of(" \t\r");
  return s.substr(begin, end - begin + 1);
}

std::vector<std::string> splitLine(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  std::string cell;
  while (std::getline(stream, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}
}  // namespace

CsvTable readCsv(const std::filesystem::path& path) {
  requireRegularFile(path);
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open for reading");
  CsvTable table;
  table.path = path;
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    // A UTF-8 byte-order mark (Excel's "CSV UTF-8") is not part of the first column's name.
    if (line_number == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    const std::string content = trim(line);
    if (content.empty() || content[0] == '#') continue;
    auto cells = splitLine(content);
    if (table.header.empty()) {
      table.header = std::move(cells);
      continue;
    }
    if (cells.size() != table.header.size()) {
      throw std::runtime_error(path.string() + ":" + std::to_string(line_number) + ": expected " +
                               std::to_string(table.header.size()) + " columns, found " + std::to_string(cells.size()));
    }
    table.rows.push_back(std::move(cells));
    table.line_numbers.push_back(line_number);
  }
  if (table.header.empty()) throw std::runtime_error(path.string() + ": empty file (no header line)");
  return table;
}

std::size_t CsvTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  throw std::runtime_error(path.string() + ": missing column '" + name + "' in the header");
}

std::string CsvTable::where(std::size_t row) const {
  return path.string() + ":" + std::to_string(line_numbers.at(row));
}

double CsvTable::number(std::size_t row, std::size_t col) const {
  const std::string& cell = rows.at(row).at(col);
  std::size_t consumed = 0;
  double value = 0.0;
  try {
    value = std::stod(cell, &consumed);
  } catch (const std::exception&) {
    consumed = 0;
  }
  if (cell.empty() || consumed != cell.size())
    throw std::runtime_error(where(row) + ": column '" + header.at(col) + "': '" + cell + "' is not a number");
  if (!std::isfinite(value))
    throw std::runtime_error(where(row) + ": column '" + header.at(col) + "': value is not finite");
  return value;
}

std::string formatNumber(double value, int significant_digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", significant_digits, value);
  return buffer;
}

}  // namespace mire::support
