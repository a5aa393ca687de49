// Shared parts of the HTML reports (see report_html.hpp).
#include "report_html.hpp"

#include "commands.hpp"
#include "mire/support/atomic_file.hpp"

#include <stdexcept>

namespace mire::app {

std::string commandLineText(const std::vector<std::string>& command_line) {
  std::string out;
  for (const auto& word : command_line) {
    const bool plain = !word.empty() && word.find_first_not_of(
                                            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                            "0123456789-_=./,:+@%") == std::string::npos;
    std::string quoted = word;
    if (!plain) {
      quoted = "'";
      for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      quoted += "'";
    }
    out += (out.empty() ? "" : " ") + quoted;
  }
  return out;
}

void addProvenance(report::HtmlReport& report, const ReportProvenance& provenance) {
  std::vector<report::InputFile> inputs;
  for (const auto& input : provenance.inputs) inputs.push_back({input.path, input.option});
  report.provenance(commandLineText(provenance.command_line), inputs, versionString());
}

void writeHtml(const std::filesystem::path& path, const report::HtmlReport& report) {
  support::writeFileAtomically(path, report.html());
}

std::vector<std::string> writeSvgFiles(const std::filesystem::path& dir, const std::vector<NamedFigure>& figures) {
  std::vector<std::string> written;
  for (const NamedFigure& f : figures) {
    std::string svg;
    try {
      svg = report::renderSvg(f.figure, std::filesystem::path(f.file).stem().string());
    } catch (const std::invalid_argument&) {
      continue;  // data the figure cannot show: report.html names it and why
    }
    support::writeFileAtomically(dir / f.file, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + svg);
    written.push_back(f.file);
  }
  return written;
}

}  // namespace mire::app
