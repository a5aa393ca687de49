#pragma once
// A self-contained HTML report (doc/plots.md): one file, CSS inline, figures inline as SVG, no
// script and no network; print CSS so a browser prints it to A4 PDF with figures and tables
// unbroken. Every text given is escaped.
#include "mire/report/figure.hpp"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace mire::report {

// "1.2346 ± 0.0012": σ rounded to two significant digits, the value to the same decimal place;
// a σ that is not finite or ≤ 0 prints the value with `fallback_decimals` and no ±.
std::string withSigma(double value, double sigma, int fallback_decimals = 4);

// A result with its standard uncertainty, in display units.
struct ResultRow {
  std::string name, unit;
  double value = 0.0, sigma = 0.0;  // sigma ≤ 0 or NaN: no uncertainty (a fixed parameter)
  std::string note;                 // e.g. "fixed", "prior"
};

struct InputFile {
  std::filesystem::path path;
  std::string role;  // the option that named it, e.g. "--poses"
};

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);
  // A section heading (h2); subsequent content belongs to it.
  void section(const std::string& heading);
  void subsection(const std::string& heading);
  void paragraph(const std::string& text);
  // A lead paragraph in large type: the result and its uncertainty, first thing on the page.
  void lead(const std::string& text);
  void keyValues(const std::vector<std::pair<std::string, std::string>>& rows);
  // Columns after the first are right-aligned (numbers).
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  void results(const std::vector<ResultRow>& rows);
  // A figure that cannot be drawn (renderSvg throws std::invalid_argument) becomes a paragraph
  // naming it and the reason; the rest of the page is written.
  void figure(const Figure& figure, const std::string& caption);
  void preformatted(const std::string& text);
  // A paragraph ending in a link: `text` then <a href="href">label</a> (a relative path to a file
  // beside the page: the report stays offline).
  void link(const std::string& text, const std::string& label, const std::string& href);
  // The inputs' table of provenance(): role, path, size and SHA-256 of each file or folder.
  void inputTable(const std::vector<InputFile>& inputs);
  // The command line and every input file's size and SHA-256 (unreadable files say so).
  void provenance(const std::string& command_line, const std::vector<InputFile>& inputs, const std::string& version);
  std::string html() const;

 private:
  std::string title_, body_;
  int figures_ = 0;
};

}  // namespace mire::report
