// SVG figures: the geometry read back from the markup (tick positions linear in their labels,
// data and error bars where the ticks say, bar lengths, the scale arrow's length), legends naming
// only what is drawn, no two texts overlapping, and well-formed XML throughout.
#include "mire/report/figure.hpp"
#include "mire/report/svg.hpp"
#include "svg_document.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace mire::report;
using mire::test::XmlDocument;
using mire::test::XmlElement;

struct Box {
  double x0, y0, x1, y1;
};

// The box a <text> covers, with the same width estimate the layout uses.
Box textBox(const XmlElement& e) {
  const double fs = e.number("font-size"), w = textWidth(e.text, fs), x = e.number("x"), y = e.number("y");
  const std::string anchor = e.attributes.at("text-anchor");
  const double shift = anchor == "middle" ? w / 2.0 : anchor == "end" ? w : 0.0;
  if (e.attributes.count("transform"))  // rotate(-90 x y): reads upward from (x, y)
    return {x - 0.8 * fs, y - w + shift, x + 0.2 * fs, y + shift};
  return {x - shift, y - 0.8 * fs, x - shift + w, y + 0.2 * fs};
}

void expectNoTextOverlap(const XmlDocument& doc) {
  const auto texts = doc.named("text");
  for (std::size_t i = 0; i < texts.size(); ++i)
    for (std::size_t j = i + 1; j < texts.size(); ++j) {
      const Box a = textBox(*texts[i]), b = textBox(*texts[j]);
      const bool overlap = a.x0 < b.x1 - 0.5 && b.x0 < a.x1 - 0.5 && a.y0 < b.y1 - 0.5 && b.y0 < a.y1 - 0.5;
      EXPECT_FALSE(overlap) << "'" << texts[i]->text << "' and '" << texts[j]->text << "' overlap";
    }
}

// pixel = a + b·value along one axis, fitted on its first and last labelled ticks; checks the others.
struct AxisFit {
  double a = 0.0, b = 0.0;
  double operator()(double v) const { return a + b * v; }
};

AxisFit fitAxis(const XmlDocument& doc, bool x_axis) {
  const auto labels = doc.withClass("text", x_axis ? "x" : "y");
  std::vector<std::pair<double, double>> points;  // value, pixel
  for (const auto* label : labels)
    if (label->hasClass("tick-label"))
      points.push_back({std::stod(label->text), x_axis ? label->number("x") : label->number("y") - 0.35 * 11.0});
  EXPECT_GE(points.size(), 3u);
  AxisFit fit;
  fit.b = (points.back().second - points.front().second) / (points.back().first - points.front().first);
  fit.a = points.front().second - fit.b * points.front().first;
  for (const auto& [value, pixel] : points) EXPECT_NEAR(fit(value), pixel, 0.03) << "tick " << value;
  // The tick marks sit under their labels.
  const auto ticks = doc.withClass("line", x_axis ? "x" : "y");
  EXPECT_EQ(ticks.size(), points.size());
  for (std::size_t i = 0; i < std::min(ticks.size(), points.size()); ++i)
    EXPECT_NEAR(ticks[i]->number(x_axis ? "x1" : "y1"), points[i].second, 0.03);
  return fit;
}

Panel linePanel() {
  Panel p;
  p.title = "residual against time";
  p.x = makeAxis("time", "s");
  p.y = makeAxis("residual", "mm");
  Series s;
  s.label = "measured";
  s.x = {0, 2, 5, 7.5, 10};
  s.y = {10, 35, 50, 80, 95};
  s.sigma = {2, 2, 5, 0, 2};
  p.series.push_back(s);
  Band band;
  band.label = "±1σ predicted";
  band.x = {0, 10};
  band.low = {0, 85};
  band.high = {20, 105};
  p.bands.push_back(band);
  return p;
}

TEST(Figure, TicksPointsAndErrorBarsAgree) {
  Figure figure;
  figure.panels.push_back(linePanel());
  const XmlDocument doc(renderSvg(figure));
  const AxisFit x = fitAxis(doc, true), y = fitAxis(doc, false);
  EXPECT_GT(x.b, 0.0);
  EXPECT_LT(y.b, 0.0);  // up is smaller y
  const auto points = doc.withClass("circle", "point");
  ASSERT_EQ(points.size(), 5u);
  EXPECT_NEAR(points[2]->number("cx"), x(5.0), 0.02);
  EXPECT_NEAR(points[2]->number("cy"), y(50.0), 0.02);
  const auto bars = doc.withClass("line", "error-bar");
  ASSERT_EQ(bars.size(), 4u);  // σ = 0 draws none
  EXPECT_NEAR(bars[2]->number("y1") - bars[2]->number("y2"), 2.0 * 5.0 * -y.b, 0.03);
  EXPECT_EQ(doc.withClass("polygon", "band").size(), 1u);
  expectNoTextOverlap(doc);
}

TEST(Figure, BarLengthsAreProportionalOnLinearAndLogAxes) {
  Panel p;
  p.x = makeAxis("parameter", "");
  p.y = makeAxis("spread", "mm");
  p.y.include_zero = true;
  p.categories = {"a", "b", "c"};
  Series s;
  s.mark = Mark::bars;
  s.x = {0, 1, 2};
  s.y = {1, 2, 4};
  p.series.push_back(s);
  Figure figure;
  figure.panels.push_back(p);
  const XmlDocument linear(renderSvg(figure));
  auto rects = linear.withClass("rect", "bar");
  ASSERT_EQ(rects.size(), 3u);
  const double h1 = rects[0]->number("height");
  EXPECT_NEAR(rects[1]->number("height"), 2 * h1, 0.03);
  EXPECT_NEAR(rects[2]->number("height"), 4 * h1, 0.03);
  // The bars stand on zero: same bottom edge.
  for (const auto* r : rects) EXPECT_NEAR(r->number("y") + r->number("height"), rects[0]->number("y") + h1, 0.02);

  figure.panels[0].y.scale = Scale::log10;
  figure.panels[0].series[0].y = {1e-3, 1e-2, 1e-1};
  const XmlDocument log(renderSvg(figure));
  rects = log.withClass("rect", "bar");
  ASSERT_EQ(rects.size(), 3u);
  const double decade = rects[1]->number("height") - rects[0]->number("height");
  EXPECT_GT(decade, 10.0);
  EXPECT_NEAR(rects[2]->number("height") - rects[1]->number("height"), decade, 0.03);
  EXPECT_FALSE(log.withClass("text", "tick-label").empty());
}

TEST(Figure, LegendNamesOnlyWhatIsDrawn) {
  Panel p = linePanel();
  Series rejected;
  rejected.label = "rejected points";  // none: no legend entry
  rejected.mark = Mark::points;
  p.series.push_back(rejected);
  Series unnamed;
  unnamed.x = {1, 2};
  unnamed.y = {3, 4};
  p.series.push_back(unnamed);
  Figure figure;
  figure.panels.push_back(p);
  const XmlDocument doc(renderSvg(figure));
  std::vector<std::string> legend;
  for (const auto* t : doc.withClass("text", "legend")) legend.push_back(t->text);
  EXPECT_EQ(legend, (std::vector<std::string>{"measured", "±1σ predicted"}));
}

TEST(Figure, VectorFieldScaleArrowStatesItsMagnification) {
  Panel p;
  p.x = makeAxis("u", "px");
  p.y = makeAxis("v", "px");
  p.x.min = 0, p.x.max = 640, p.x.tight = true;
  p.y.min = 0, p.y.max = 480, p.y.tight = true, p.y.inverted = true;
  p.equal_aspect = true;
  VectorField field;
  field.magnification = 100.0;
  field.unit = "px";
  field.sets.push_back({"inliers", {100, 300, 500}, {100, 240, 400}, {0.1, -0.2, 0.3}, {0.1, 0.2, 0.0}, ""});
  p.vectors = field;
  Figure figure;
  figure.panels.push_back(p);
  figure.panel_width = 520;
  figure.panel_height = 460;
  const XmlDocument doc(renderSvg(figure));
  const AxisFit x = fitAxis(doc, true), y = fitAxis(doc, false);
  EXPECT_NEAR(x.b, y.b, 1e-4) << "equal aspect (y grows downward: rows)";
  EXPECT_NEAR(y(0.0), doc.withClass("rect", "frame")[0]->number("y"), 0.02) << "row 0 at the top";
  const auto vectors = doc.withClass("line", "vector");
  ASSERT_EQ(vectors.size(), 3u);
  EXPECT_NEAR(vectors[1]->number("x2") - vectors[1]->number("x1"), -0.2 * 100.0 * x.b, 0.03);
  const auto arrow = doc.withClass("line", "scale-arrow");
  ASSERT_EQ(arrow.size(), 1u);
  const double length = arrow[0]->number("x2") - arrow[0]->number("x1");
  const auto legend = doc.withClass("text", "legend");
  ASSERT_EQ(legend.size(), 2u);
  const std::string label = legend[1]->text;  // "0.5 px (arrows ×100)"
  EXPECT_NE(label.find("\xC3\x97"
                       "100"),
            std::string::npos)
      << label;
  EXPECT_NEAR(length, std::stod(label) * 100.0 * x.b, 0.03) << label;
  expectNoTextOverlap(doc);
}

TEST(Figure, HeatMapCellsAndColourBar) {
  Panel p;
  p.x = makeAxis("u", "px");
  p.y = makeAxis("v", "px");
  p.x.min = 0, p.x.max = 64, p.x.tight = true;
  p.y.min = 0, p.y.max = 48, p.y.tight = true, p.y.inverted = true;
  p.equal_aspect = true;
  HeatMap map;
  map.columns = 4, map.rows = 3, map.cell_width = 16, map.cell_height = 16;
  map.values = {0.02, 0.05, 0.1, 0.2, 0.03, NAN, 0.3, 0.5, 0.04, 0.06, 0.08, 0.4};
  map.label = "σ projection", map.unit = "px", map.scale = Scale::log10;
  p.heat_map = map;
  Figure figure;
  figure.panels.push_back(p);
  const XmlDocument doc(renderSvg(figure));
  const auto cells = doc.withClass("rect", "cell");
  EXPECT_EQ(cells.size(), 11u);  // the NaN cell blank
  EXPECT_NE(cells.front()->attributes.at("fill"), cells.back()->attributes.at("fill"));
  EXPECT_EQ(doc.withClass("rect", "colour-bar").size(), 64u);
  EXPECT_FALSE(doc.withClass("text", "colour").empty());
  expectNoTextOverlap(doc);
}

// Panels in a grid with long titles, long vertical category labels, a 12-decade log axis and a
// heat map beside: still no text over another.
TEST(Figure, ManyPanelsNoTextOverlaps) {
  Figure figure;
  figure.title = "a figure title that is rather long for its width, on purpose";
  figure.columns = 2;
  figure.panel_width = 380;
  figure.panel_height = 280;
  figure.panels.push_back(linePanel());
  figure.panels[0].title = std::string(120, 'T');
  Panel bars;
  bars.x = makeAxis("direction", "");
  bars.y = makeAxis("singular value", "");
  bars.y.scale = Scale::log10;
  Series s;
  s.mark = Mark::bars;
  for (int k = 0; k < 24; ++k) {
    bars.categories.push_back("parameter_name_" + std::to_string(k));
    s.x.push_back(k);
    s.y.push_back(std::pow(10.0, 4.0 - k * 0.5));
  }
  bars.series.push_back(s);
  figure.panels.push_back(bars);
  Panel wide;
  wide.x = makeAxis("pose", "");
  wide.y = makeAxis("value", "m");
  Series w;
  for (int k = 0; k < 50; ++k) {
    w.x.push_back(123456.0 + k * 1000.0);
    w.y.push_back(1e-4 * k);
  }
  wide.series.push_back(w);
  figure.panels.push_back(wide);
  const XmlDocument doc(renderSvg(figure, "many"));
  expectNoTextOverlap(doc);
  EXPECT_EQ(doc.withClass("text", "panel-title").size(), 1u);
  EXPECT_EQ(doc.named("clipPath").size(), 3u);
  EXPECT_EQ(doc.named("clipPath")[2]->attributes.at("id"), "many-clip2");
}

TEST(Figure, PanelsAlignWhenOnlyOneHasALegend) {
  Figure figure;
  figure.columns = 2;
  figure.panels = {linePanel(), linePanel()};
  figure.panels[1].series[0].label.clear();
  figure.panels[1].bands[0].label.clear();
  const XmlDocument doc(renderSvg(figure));
  const auto frames = doc.withClass("rect", "frame");
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0]->attributes.at("height"), frames[1]->attributes.at("height"));
  EXPECT_EQ(doc.withClass("text", "legend").size(), 2u);
}

TEST(Figure, EscapesTextAndRejectsMismatchedSeries) {
  Panel p = linePanel();
  p.title = "a < b & \"c\"";
  Figure figure;
  figure.panels.push_back(p);
  const XmlDocument doc(renderSvg(figure));
  EXPECT_EQ(doc.withClass("text", "panel-title")[0]->text, "a < b & \"c\"");
  figure.panels[0].series[0].sigma.pop_back();
  EXPECT_THROW(renderSvg(figure), std::invalid_argument);
}

TEST(Figure, Nice125) {
  EXPECT_DOUBLE_EQ(nice125(0.0031), 0.002);
  EXPECT_DOUBLE_EQ(nice125(0.0037), 0.005);
  EXPECT_DOUBLE_EQ(nice125(8.0), 10.0);
  EXPECT_EQ(viridis(0.0), "#440154");
  EXPECT_EQ(viridis(1.0), "#fde725");
}

}  // namespace
