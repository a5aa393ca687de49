// Self-contained HTML report (see html.hpp).
#include "mire/report/html.hpp"

#include "mire/report/sha256.hpp"
#include "mire/report/svg.hpp"

#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>

namespace mire::report {
namespace {

// Screen and print styles: A4 with 14 mm margins; figures, tables and headings kept whole.
constexpr const char* kStyle = R"(
body { font-family: "DejaVu Sans", Helvetica, Arial, sans-serif; font-size: 14px; color: #222;
       max-width: 980px; margin: 24px auto; padding: 0 16px; line-height: 1.4; }
h1 { font-size: 24px; margin: 0 0 8px; } h2 { font-size: 19px; margin: 28px 0 8px; border-bottom: 1px solid #ccc; }
h3 { font-size: 16px; margin: 18px 0 6px; }
p.lead { font-size: 17px; background: #f3f6fa; border-left: 4px solid #1f77b4; padding: 8px 12px; }
table { border-collapse: collapse; margin: 8px 0 14px; font-size: 13px; }
th, td { border: 1px solid #ccc; padding: 3px 8px; vertical-align: top; }
th { background: #f0f0f0; text-align: left; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.hash { font-family: "DejaVu Sans Mono", monospace; font-size: 10px; word-break: break-all; }
td.num, table.inputs td:first-child { white-space: nowrap; }
figure { margin: 12px 0 18px; } figure svg { max-width: 100%; height: auto; display: block; }
figcaption { font-size: 13px; color: #444; margin-top: 4px; }
pre { background: #f7f7f7; padding: 8px; font-size: 12px; overflow-x: auto; white-space: pre-wrap; }
@page { size: A4; margin: 14mm; }
@media print {
  body { max-width: none; margin: 0; padding: 0; font-size: 11px; }
  h2 { break-after: avoid; } h3 { break-after: avoid; }
  figure, table, pre, p.lead { break-inside: avoid; }
  figure svg { max-height: 120mm; width: auto; max-width: 100%; }
}
)";

std::string cell(const std::string& text, const std::string& css = "") {
  return (css.empty() ? "<td>" : "<td class=\"" + css + "\">") + escapeXml(text) + "</td>";
}

std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string byteCount(std::uintmax_t bytes) {
  char buffer[32];
  if (bytes < 10000)
    std::snprintf(buffer, sizeof buffer, "%ju B", bytes);
  else if (bytes < 10000000)
    std::snprintf(buffer, sizeof buffer, "%.1f kB", static_cast<double>(bytes) / 1e3);
  else
    std::snprintf(buffer, sizeof buffer, "%.1f MB", static_cast<double>(bytes) / 1e6);
  return buffer;
}

}  // namespace

std::string withSigma(double value, double sigma, int fallback_decimals) {
  if (!std::isfinite(value)) return "n/a";
  if (!(sigma > 0.0) || !std::isfinite(sigma)) return fixed(value, fallback_decimals);
  // Two significant digits of σ fix the last decimal of both (GUM 7.2.6).
  const int decimals = std::max(0, 1 - static_cast<int>(std::floor(std::log10(sigma))));
  if (decimals > 12) return fixed(value, fallback_decimals) + " \xC2\xB1 " + fixed(sigma, 12);
  return fixed(value, decimals) + " \xC2\xB1 " + fixed(sigma, decimals);
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::section(const std::string& heading) { body_ += "<h2>" + escapeXml(heading) + "</h2>\n"; }

void HtmlReport::subsection(const std::string& heading) { body_ += "<h3>" + escapeXml(heading) + "</h3>\n"; }

void HtmlReport::paragraph(const std::string& text) { body_ += "<p>" + escapeXml(text) + "</p>\n"; }

void HtmlReport::lead(const std::string& text) { body_ += "<p class=\"lead\">" + escapeXml(text) + "</p>\n"; }

void HtmlReport::keyValues(const std::vector<std::pair<std::string, std::string>>& rows) {
  body_ += "<table class=\"key-values\">\n";
  for (const auto& [key, value] : rows) body_ += "<tr><th>" + escapeXml(key) + "</th>" + cell(value) + "</tr>\n";
  body_ += "</table>\n";
}

void HtmlReport::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  body_ += "<table>\n<tr>";
  for (const auto& h : header) body_ += "<th>" + escapeXml(h) + "</th>";
  body_ += "</tr>\n";
  for (const auto& row : rows) {
    body_ += "<tr>";
    for (std::size_t i = 0; i < row.size(); ++i) body_ += cell(row[i], i == 0 ? "" : "num");
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlReport::results(const std::vector<ResultRow>& rows) {
  bool notes = false;  // the note column only when a row has one
  for (const auto& r : rows) notes = notes || !r.note.empty();
  body_ += std::string("<table class=\"results\">\n<tr><th>quantity</th><th>unit</th><th>value ± σ</th>") +
           (notes ? "<th></th>" : "") + "</tr>\n";
  for (const auto& r : rows)
    body_ += "<tr>" + cell(r.name) + cell(r.unit) + cell(withSigma(r.value, r.sigma), "num") +
             (notes ? cell(r.note) : std::string()) + "</tr>\n";
  body_ += "</table>\n";
}

void HtmlReport::figure(const Figure& figure, const std::string& caption) {
  ++figures_;
  std::string svg;
  try {
    svg = renderSvg(figure, "f" + std::to_string(figures_));
  } catch (const std::invalid_argument& error) {
    // Data a figure cannot show (e.g. nothing positive for a log axis) must not cost the command its
    // results: the page says which figure is missing and why.
    body_ += "<p class=\"missing-figure\">Figure " + std::to_string(figures_) + " not drawn (" +
             escapeXml(error.what()) + "): " + escapeXml(caption) + "</p>\n";
    return;
  }
  body_ += "<figure>\n" + svg + "<figcaption>Figure " + std::to_string(figures_) + ". " + escapeXml(caption) +
           "</figcaption>\n</figure>\n";
}

void HtmlReport::preformatted(const std::string& text) { body_ += "<pre>" + escapeXml(text) + "</pre>\n"; }

void HtmlReport::provenance(const std::string& command_line, const std::vector<InputFile>& inputs,
                            const std::string& version) {
  section("Provenance");
  keyValues({{"command", command_line}, {"mire version", version}});
  inputTable(inputs);
}

void HtmlReport::inputTable(const std::vector<InputFile>& inputs) {
  body_ += "<table class=\"inputs\">\n<tr><th>input</th><th>file</th><th>size</th><th>SHA-256</th></tr>\n";
  for (const auto& input : inputs) {
    std::string size = "-", digest;
    try {
      if (std::filesystem::is_directory(input.path)) {  // a folder of images: its manifest's digest
        const FolderDigest folder = sha256Folder(input.path);
        size = std::to_string(folder.files) + " files";
        digest = folder.sha256 + " (sha256sum manifest)";
      } else {
        size = byteCount(std::filesystem::file_size(input.path));
        digest = sha256File(input.path);
      }
    } catch (const std::exception& error) {
      digest = std::string("unreadable: ") + error.what();
    }
    body_ +=
        "<tr>" + cell(input.role) + cell(input.path.string()) + cell(size, "num") + cell(digest, "hash") + "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlReport::link(const std::string& text, const std::string& label, const std::string& href) {
  body_ += "<p>" + escapeXml(text) + " <a href=\"" + escapeXml(href) + "\">" + escapeXml(label) + "</a></p>\n";
}

std::string HtmlReport::html() const {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>" + escapeXml(title_) +
         "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n<h1>" + escapeXml(title_) + "</h1>\n" + body_ +
         "</body>\n</html>\n";
}

}  // namespace mire::report
