// Report of `mire identify` (see identify_report.hpp).
#include "identify_report.hpp"
#include "number_text.hpp"
#include "report_html.hpp"

#include "mire/support/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace mire::app {

void writeIdentifyReport(const std::filesystem::path& dir, const IdentifyReportData& data) {
  std::filesystem::create_directories(dir);
  writeSvgFiles(dir, identifyFigures(data));

  std::ostringstream md;
  md << "# mire identify report\n\n";
  md << "Command: `"
     << (data.provenance.command_line.empty() ? data.command_line : commandLineText(data.provenance.command_line))
     << "`\n\n";
  md << "Model: " << data.model_label << "\n\n";
  md << "```\n" << data.summary_text << "```\n\n";
  md << "## Residuals per pose and leg\n\n![residuals after identification](residuals.svg)\n\n"
     << "![residuals before identification](residuals_before.svg)\n\n";
  md << "## Identifiability\n\n![singular values](singular_values.svg)\n\n```\n"
     << data.result.identifiability.text() << "\n```\n\n";
  if (data.study) md << "## Monte-Carlo study\n\n![spreads](monte_carlo_spread.svg)\n\n";
  // The mechanism's own joints and units (a Delta has 3 legs in deg, a hexapod 6 in mm).
  const std::vector<mechanism::Unit> units = data.result.model.mechanism->jointUnits();
  md << "## Poses\n\n| pose |";
  for (std::size_t k = 0; k < units.size(); ++k)
    md << " q" << k + 1 << " - f (" << mechanism::displayUnitName(units[k]) << ") |";
  md << " outlier |\n|---|";
  for (std::size_t k = 0; k < units.size(); ++k) md << "---|";
  md << "---|\n";
  for (const auto& p : data.result.poses) {
    md << "| " << p.id;
    for (int k = 0; k < p.residual.size() && k < static_cast<int>(units.size()); ++k)
      md << " | " << format("%+.4f", mechanism::toDisplay(units[static_cast<std::size_t>(k)], p.residual[k]));
    md << " | " << (p.outlier ? "yes" : "") << " |\n";
  }
  support::writeFileAtomically(dir / "report.md", md.str());
  writeIdentifyReportJson(dir / "report.json", data);
  writeIdentifyReportHtml(dir / "report.html", data);
}

}  // namespace mire::app
