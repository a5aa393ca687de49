// The HTML report: one well-formed file (parsed as XML), nothing fetched from the network, figures
// inline, value ± σ to the σ's two significant digits, input files with their SHA-256.
#include "mire/report/html.hpp"
#include "mire/report/sha256.hpp"
#include "svg_document.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

namespace {

using namespace mire::report;
using mire::test::XmlDocument;

TEST(HtmlReport, ValueWithSigmaHasTheSigmasDecimals) {
  EXPECT_EQ(withSigma(1.234567, 0.0012), "1.2346 \xC2\xB1 0.0012");
  EXPECT_EQ(withSigma(250.4, 13.0), "250 \xC2\xB1 13");
  EXPECT_EQ(withSigma(-0.5, 0.25), "-0.50 \xC2\xB1 0.25");
  EXPECT_EQ(withSigma(3.0, 0.0), "3.0000");
  EXPECT_EQ(withSigma(NAN, 1.0), "n/a");
}

TEST(HtmlReport, SelfContainedAndWellFormed) {
  const auto input = std::filesystem::temp_directory_path() / ("mire-html-" + std::to_string(::getpid()) + ".csv");
  std::ofstream(input) << "pose_id,x\np1,1\n";
  HtmlReport report("mire calibrate <report>");
  report.lead("focal length 812.3 ± 0.4 px");
  report.section("Result");
  report.results({{"fx", "px", 812.31, 0.42, ""}, {"k3", "", 0.0, 0.0, "fixed"}});
  report.keyValues({{"views", "24"}, {"rms", "0.21 px"}});
  report.table({"pose", "q1 (deg)"}, {{"p1", "+0.01"}, {"p2", "-0.02"}});
  Figure figure;
  Panel panel;
  panel.x = makeAxis("x", "mm");
  panel.y = makeAxis("y", "mm");
  panel.series.push_back({"data", Mark::line, {0, 1}, {0, 1}, {}, ""});
  figure.panels = {panel, panel};
  report.figure(figure, "two panels & a caption");
  report.figure(figure, "the same again");
  report.preformatted("a <pre> block");
  report.provenance("mire calibrate --target t.yaml", {{input, "--target"}, {"/nonexistent/x.yaml", "--images"}},
                    "0.1.0");
  const std::string html = report.html();
  const XmlDocument doc(html);  // XHTML-compatible: parses as XML
  EXPECT_EQ(doc.named("svg").size(), 2u);
  EXPECT_EQ(doc.named("figcaption").size(), 2u);
  EXPECT_EQ(doc.named("h1")[0]->text, "mire calibrate <report>");
  // Ids unique across the page's figures.
  std::set<std::string> ids;
  for (const auto* clip : doc.named("clipPath")) EXPECT_TRUE(ids.insert(clip->attributes.at("id")).second);
  EXPECT_EQ(ids.size(), 4u);
  for (const char* network : {"<script", "<link", "src=", "https://", "@import", "url(http"})
    EXPECT_EQ(html.find(network), std::string::npos) << network;
  EXPECT_NE(html.find("@media print"), std::string::npos);
  EXPECT_NE(html.find(sha256File(input)), std::string::npos);
  EXPECT_NE(html.find("unreadable"), std::string::npos);
  EXPECT_NE(html.find("812.31 \xC2\xB1 0.42"), std::string::npos);
  std::filesystem::remove(input);
}

TEST(HtmlReport, AFigureThatCannotBeDrawnIsNamedNotFatal) {
  HtmlReport report("r");
  Figure figure;
  Panel panel;
  panel.y = makeAxis("sigma", "mm", Scale::log10);
  panel.series.push_back({"zero", Mark::points, {0, 1}, {0.0, 0.0}, {}, ""});  // nothing positive
  figure.panels = {panel};
  report.figure(figure, "spreads");
  report.paragraph("after");
  const std::string html = report.html();
  const XmlDocument doc(html);
  EXPECT_TRUE(doc.named("svg").empty());
  const auto missing = doc.withClass("p", "missing-figure");
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0]->text,
            "Figure 1 not drawn (figure axis 'sigma (mm)': no positive value on a log axis): spreads");
  EXPECT_NE(html.find("<p>after</p>"), std::string::npos);
}

}  // namespace
