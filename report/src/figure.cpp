// SVG figures (see figure.hpp): layout of each panel, its axes, data and legend.
#include "mire/report/figure.hpp"

#include "mire/report/svg.hpp"
#include "mire/report/ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace mire::report {
namespace {

constexpr double kTickFont = 11.0, kLabelFont = 12.0, kTitleFont = 13.0, kLegendRow = 17.0;

std::string axisTitle(const Axis& axis) { return axis.unit.empty() ? axis.label : axis.label + " (" + axis.unit + ")"; }

// The text, cut with an ellipsis when it is wider than `room` at `font`.
std::string fitted(const std::string& text, double room, double font) {
  if (textWidth(text, font) <= room) return text;
  std::string cut = text;
  while (!cut.empty() && textWidth(cut + "\xE2\x80\xA6", font) > room) {
    cut.pop_back();
    while (!cut.empty() && (static_cast<unsigned char>(cut.back()) & 0xC0) == 0x80) cut.pop_back();  // whole glyphs
    if (!cut.empty() && (static_cast<unsigned char>(cut.back()) & 0x80)) cut.pop_back();
  }
  return cut + "\xE2\x80\xA6";
}

double tickLabelWidth(const Tick& tick) {
  return textWidth(tick.label + tick.exponent, kTickFont);  // the raised exponent counted at full size
}

// The values one axis must show (log axes: the positive ones only).
struct Extent {
  double low = std::numeric_limits<double>::infinity(), high = -std::numeric_limits<double>::infinity();
  void add(double v, Scale scale) {
    if (!std::isfinite(v) || (scale == Scale::log10 && !(v > 0.0))) return;
    low = std::min(low, v);
    high = std::max(high, v);
  }
  bool empty() const { return !(low <= high); }
};

void checkLengths(const Panel& panel) {
  for (const auto& s : panel.series)
    if (s.x.size() != s.y.size() || (!s.sigma.empty() && s.sigma.size() != s.y.size()))
      throw std::invalid_argument("figure series '" + s.label + "': x, y and sigma lengths differ");
  for (const auto& b : panel.bands)
    if (b.x.size() != b.low.size() || b.x.size() != b.high.size())
      throw std::invalid_argument("figure band '" + b.label + "': x, low and high lengths differ");
  if (panel.vectors)
    for (const auto& v : panel.vectors->sets)
      if (v.x.size() != v.y.size() || v.x.size() != v.dx.size() || v.x.size() != v.dy.size())
        throw std::invalid_argument("figure vectors '" + v.label + "': lengths differ");
  if (panel.heat_map &&
      panel.heat_map->values.size() != static_cast<std::size_t>(panel.heat_map->columns) * panel.heat_map->rows)
    throw std::invalid_argument("figure heat map: " + std::to_string(panel.heat_map->values.size()) + " values for a " +
                                std::to_string(panel.heat_map->columns) + " x " + std::to_string(panel.heat_map->rows) +
                                " grid");
}

Extent xExtent(const Panel& panel) {
  Extent e;
  const Scale s = panel.x.scale;
  for (const auto& series : panel.series)
    for (const double v : series.x) e.add(v, s);
  for (const auto& b : panel.bands)
    for (const double v : b.x) e.add(v, s);
  if (panel.vectors)
    for (const auto& v : panel.vectors->sets)
      for (const double x : v.x) e.add(x, s);
  if (panel.heat_map) {
    e.add(panel.heat_map->x0, s);
    e.add(panel.heat_map->x0 + panel.heat_map->columns * panel.heat_map->cell_width, s);
  }
  return e;
}

Extent yExtent(const Panel& panel) {
  Extent e;
  const Scale s = panel.y.scale;
  for (const auto& series : panel.series)
    for (std::size_t i = 0; i < series.y.size(); ++i) {
      const double sigma = series.sigma.empty() ? 0.0 : series.sigma[i];
      e.add(series.y[i], s);
      if (sigma > 0.0) {
        e.add(series.y[i] + sigma, s);
        e.add(series.y[i] - sigma, s);
      }
    }
  for (const auto& b : panel.bands) {
    for (const double v : b.low) e.add(v, s);
    for (const double v : b.high) e.add(v, s);
  }
  for (const auto& r : panel.references) e.add(r.value, s);
  if (panel.vectors)
    for (const auto& v : panel.vectors->sets)
      for (const double y : v.y) e.add(y, s);
  if (panel.heat_map) {
    e.add(panel.heat_map->y0, s);
    e.add(panel.heat_map->y0 + panel.heat_map->rows * panel.heat_map->cell_height, s);
  }
  return e;
}

TickSet axisTicks(const Axis& axis, Extent e, int max_count) {
  if (axis.min) e.low = *axis.min;
  if (axis.max) e.high = *axis.max;
  if (axis.scale == Scale::log10) {
    if (e.empty())
      throw std::invalid_argument("figure axis '" + axisTitle(axis) + "': no positive value on a log axis");
    TickSet set = logTicks(e.low, e.high);
    if (axis.tight) set.low = e.low, set.high = e.high;
    return set;
  }
  if (e.empty()) e.low = 0.0, e.high = 1.0;
  if (axis.include_zero) e.low = std::min(e.low, 0.0), e.high = std::max(e.high, 0.0);
  if (axis.symmetric) {
    const double m = std::max(std::abs(e.low), std::abs(e.high));
    e.low = -m, e.high = m;
  }
  TickSet set = linearTicks(e.low, e.high, max_count);
  if (axis.tight || (axis.min && axis.max)) {
    set.low = e.low, set.high = e.high;
    std::vector<Tick> inside;
    const double slack = 1e-9 * (e.high - e.low);
    for (const auto& t : set.ticks)
      if (t.value >= e.low - slack && t.value <= e.high + slack) inside.push_back(t);
    set.ticks = inside;
  }
  return set;
}

// Value → pixel along one axis.
struct Mapping {
  double low = 0.0, high = 1.0, from = 0.0, to = 1.0;  // data range → pixel range
  bool log = false;
  double operator()(double v) const {
    if (log) {
      const double l = std::log10(std::max(v, 1e-300));
      return from + (l - std::log10(low)) / (std::log10(high) - std::log10(low)) * (to - from);
    }
    return from + (v - low) / (high - low) * (to - from);
  }
};

struct LegendEntry {
  enum class Kind { line, point, box, band, arrow } kind = Kind::line;
  std::string label, colour;
  bool dashed = false;
  double arrow_length = 0.0;  // px, Kind::arrow
};

double entryWidth(const LegendEntry& e) {
  const double swatch = e.kind == LegendEntry::Kind::arrow ? e.arrow_length : 18.0;
  return swatch + 5.0 + textWidth(e.label, kTickFont) + 14.0;
}

int legendRows(const std::vector<LegendEntry>& entries, double width) {
  int rows = entries.empty() ? 0 : 1;
  double x = 0.0;
  for (const auto& e : entries) {
    const double w = entryWidth(e);
    if (x > 0.0 && x + w > width) ++rows, x = 0.0;
    x += w;
  }
  return rows;
}

// One panel's boxes: the plot area and where its labels go.
struct Layout {
  double left = 0.0, top = 0.0, width = 0.0, height = 0.0;  // plot area
  double box_x = 0.0, box_y = 0.0, box_w = 0.0, box_h = 0.0;
  bool vertical_categories = false;
  double category_depth = 0.0;  // px the category labels take below the axis
  int category_every = 1;       // label every n-th category when they cannot all fit
};

class PanelRenderer {
 public:
  // `legend_rows`: at least that many legend rows are reserved (panels of one figure align their
  // plot areas even when only one of them carries the legend).
  PanelRenderer(SvgWriter& svg, const Panel& panel, const std::string& clip_id, double x, double y, double w, double h,
                int legend_rows = 0)
      : svg_(svg), panel_(panel), clip_id_(clip_id), legend_rows_(legend_rows) {
    checkLengths(panel);
    layout_.box_x = x, layout_.box_y = y, layout_.box_w = w, layout_.box_h = h;
    colourSeries();
    legend_ = legendEntries();
    place();
  }

  int legendRowCount() const { return legend_rows_; }

  void render() {
    grid();
    svg_.beginClip(clip_id_, layout_.left, layout_.top, layout_.width, layout_.height);
    heatMap();
    bands();
    references();
    bars();
    lines();
    vectors();
    svg_.endClip();
    svg_.rect(layout_.left, layout_.top, layout_.width, layout_.height, "none", "#444", "frame");
    xTicks();
    yTicks();
    colourBar();
    labels();
    legend();
  }

 private:
  bool categorical() const { return !panel_.categories.empty(); }

  void colourSeries() {
    std::size_t next = 0;
    for (const auto& s : panel_.series) colours_.push_back(s.colour.empty() ? paletteColour(next++) : s.colour);
    if (panel_.vectors)
      for (const auto& v : panel_.vectors->sets)
        vector_colours_.push_back(v.colour.empty() ? paletteColour(next++) : v.colour);
  }

  std::vector<LegendEntry> legendEntries() const {
    std::vector<LegendEntry> out;
    for (std::size_t i = 0; i < panel_.series.size(); ++i) {
      const auto& s = panel_.series[i];
      if (s.label.empty() || s.y.empty()) continue;  // only what is drawn
      const auto kind = s.mark == Mark::bars     ? LegendEntry::Kind::box
                        : s.mark == Mark::points ? LegendEntry::Kind::point
                                                 : LegendEntry::Kind::line;
      out.push_back({kind, s.label, colours_[i]});
    }
    for (const auto& b : panel_.bands)
      if (!b.label.empty() && !b.x.empty()) out.push_back({LegendEntry::Kind::band, b.label, b.colour});
    for (const auto& r : panel_.references)
      if (!r.label.empty()) out.push_back({LegendEntry::Kind::line, r.label, r.colour, r.dashed});
    if (panel_.vectors)
      for (std::size_t i = 0; i < panel_.vectors->sets.size(); ++i) {
        const auto& v = panel_.vectors->sets[i];
        if (!v.label.empty() && !v.x.empty()) out.push_back({LegendEntry::Kind::line, v.label, vector_colours_[i]});
      }
    return out;
  }

  // Margins from the labels' sizes, then the ticks that fit without overlapping.
  void place() {
    const Layout& l = layout_;
    x_ticks_ = axisTicks(panel_.x, xExtent(panel_), 8);
    y_ticks_ = axisTicks(panel_.y, yExtent(panel_), 7);
    colour_ticks_ = colourTicks();
    double y_label_width = 0.0;
    for (const auto& t : y_ticks_.ticks) y_label_width = std::max(y_label_width, tickLabelWidth(t));
    const double left = l.box_x + 8.0 + kLabelFont + 6.0 + y_label_width + 6.0;
    double right = l.box_x + l.box_w - 12.0;
    if (panel_.heat_map) {
      double w = 0.0;
      for (const auto& t : colour_ticks_.ticks) w = std::max(w, tickLabelWidth(t));
      right -= 10.0 + 14.0 + 5.0 + w + 8.0 + kLabelFont + 4.0;
    }
    const double top = l.box_y + (panel_.title.empty() ? 10.0 : 8.0 + kTitleFont + 8.0);
    layout_.left = left;
    layout_.width = std::max(40.0, right - left);
    categoryLabels();
    std::vector<LegendEntry> entries = legend_;
    if (panel_.vectors)
      entries.push_back({LegendEntry::Kind::arrow,
                         "0.05 px (arrows \xC3\x97"
                         "1000)",
                         "", false, 80.0});
    legend_rows_ = std::max(legend_rows_, legendRows(entries, l.box_w - 16.0));
    const double legend_height = legend_rows_ * kLegendRow;
    const double below = 6.0 + (categorical() ? layout_.category_depth : kTickFont + 4.0) + 8.0 + kLabelFont + 4.0 +
                         (legend_height > 0.0 ? legend_height + 6.0 : 0.0);
    layout_.top = top;
    layout_.height = std::max(40.0, l.box_y + l.box_h - below - top);
    if (panel_.equal_aspect) equalAspect();
    fitTicks();
  }

  TickSet colourTicks() const {
    if (!panel_.heat_map) return {};
    Extent e;
    for (const double v : panel_.heat_map->values) e.add(v, panel_.heat_map->scale);
    Axis axis;
    axis.scale = panel_.heat_map->scale;
    axis.label = panel_.heat_map->label;
    return axisTicks(axis, e, 6);
  }

  void equalAspect() {
    const double dx = x_ticks_.high - x_ticks_.low, dy = y_ticks_.high - y_ticks_.low;
    if (!(dx > 0.0) || !(dy > 0.0)) return;
    const double scale = std::min(layout_.width / dx, layout_.height / dy);
    const double w = dx * scale, h = dy * scale;
    layout_.left += (layout_.width - w) / 2.0;
    layout_.width = w;
    layout_.height = h;
  }

  void categoryLabels() {
    if (!categorical()) return;
    const double slot = layout_.width / static_cast<double>(panel_.categories.size());
    double widest = 0.0;
    for (const auto& c : panel_.categories) widest = std::max(widest, textWidth(c, kTickFont));
    layout_.vertical_categories = widest > slot - 4.0;
    if (!layout_.vertical_categories) {
      layout_.category_depth = kTickFont + 4.0;
      return;
    }
    layout_.category_depth = widest + 4.0;
    layout_.category_every = std::max(1, static_cast<int>(std::ceil((kTickFont + 2.0) / slot)));
  }

  Mapping xMap() const {
    if (categorical())
      return {-0.5, static_cast<double>(panel_.categories.size()) - 0.5, layout_.left, layout_.left + layout_.width};
    return {x_ticks_.low, x_ticks_.high, layout_.left, layout_.left + layout_.width, panel_.x.scale == Scale::log10};
  }

  Mapping yMap() const {
    const double bottom = layout_.top + layout_.height;
    return panel_.y.inverted ? Mapping{y_ticks_.low, y_ticks_.high, layout_.top, bottom, panel_.y.scale == Scale::log10}
                             : Mapping{y_ticks_.low, y_ticks_.high, bottom, layout_.top, panel_.y.scale == Scale::log10};
  }

  // Fewer linear ticks until the labels clear each other; log labels thinned likewise.
  void fitTicks() {
    for (int count = 8; count >= 2 && !categorical(); --count) {
      if (xLabelsClear()) break;
      x_ticks_ = axisTicks(panel_.x, xExtent(panel_), count);
      if (panel_.x.scale == Scale::log10) break;
    }
    for (int count = 7; count >= 2; --count) {
      if (yLabelsClear()) break;
      y_ticks_ = axisTicks(panel_.y, yExtent(panel_), count);
      if (panel_.y.scale == Scale::log10) break;
    }
    thin(x_ticks_, xMap(), true);
    thin(y_ticks_, yMap(), false);
  }

  bool xLabelsClear() const {
    const Mapping m = xMap();
    double previous_end = -1e300;
    for (const auto& t : x_ticks_.ticks) {
      if (t.label.empty()) continue;
      const double w = tickLabelWidth(t), c = m(t.value);
      if (c - w / 2.0 < previous_end + 6.0) return false;
      previous_end = c + w / 2.0;
    }
    return true;
  }

  bool yLabelsClear() const {
    const Mapping m = yMap();
    double previous = 1e300;
    for (const auto& t : y_ticks_.ticks) {
      if (t.label.empty()) continue;
      const double y = m(t.value);
      if (std::abs(previous - y) < kTickFont + 3.0) return false;
      previous = y;
    }
    return true;
  }

  // Drops a label that would touch the previous labelled one (log axes over many decades).
  static void thin(TickSet& set, const Mapping& m, bool horizontal) {
    bool first = true;
    double previous = 0.0, previous_half = 0.0;
    for (auto& t : set.ticks) {
      if (t.label.empty()) continue;
      const double c = m(t.value);
      const double half = horizontal ? tickLabelWidth(t) / 2.0 + 3.0 : (kTickFont + 3.0) / 2.0;
      if (!first && std::abs(c - previous) < half + previous_half) {
        t.label.clear(), t.exponent.clear();
        continue;
      }
      first = false, previous = c, previous_half = half;
    }
  }

  void grid() {
    const Mapping mx = xMap(), my = yMap();
    svg_.rect(layout_.left, layout_.top, layout_.width, layout_.height, "#ffffff", "none", "plot-area");
    if (!categorical())
      for (const auto& t : x_ticks_.ticks)
        svg_.line(mx(t.value), layout_.top, mx(t.value), layout_.top + layout_.height, t.major ? "#e3e3e3" : "#f2f2f2",
                  1.0, "grid");
    for (const auto& t : y_ticks_.ticks)
      svg_.line(layout_.left, my(t.value), layout_.left + layout_.width, my(t.value), t.major ? "#e3e3e3" : "#f2f2f2",
                1.0, "grid");
  }

  void xTicks() {
    const Mapping m = xMap();
    const double bottom = layout_.top + layout_.height;
    if (categorical()) {
      for (std::size_t i = 0; i < panel_.categories.size(); ++i) {
        const double x = m(static_cast<double>(i));
        svg_.line(x, bottom, x, bottom + 4.0, "#444", 1.0, "tick x");
        if (i % static_cast<std::size_t>(layout_.category_every) != 0) continue;
        if (layout_.vertical_categories)
          svg_.text(x + 0.35 * kTickFont, bottom + 6.0, panel_.categories[i], kTickFont, Anchor::end, "tick-label x",
                    -90.0);
        else
          svg_.text(x, bottom + 6.0 + kTickFont, panel_.categories[i], kTickFont, Anchor::middle, "tick-label x");
      }
      return;
    }
    for (const auto& t : x_ticks_.ticks) {
      const double x = m(t.value);
      svg_.line(x, bottom, x, bottom + (t.major ? 5.0 : 3.0), "#444", 1.0, "tick x");
      label(t, x, bottom + 6.0 + kTickFont, Anchor::middle, "tick-label x");
    }
  }

  void yTicks() {
    const Mapping m = yMap();
    for (const auto& t : y_ticks_.ticks) {
      const double y = m(t.value);
      svg_.line(layout_.left - (t.major ? 5.0 : 3.0), y, layout_.left, y, "#444", 1.0, "tick y");
      label(t, layout_.left - 7.0, y + 0.35 * kTickFont, Anchor::end, "tick-label y");
    }
  }

  void label(const Tick& t, double x, double y, Anchor anchor, const std::string& css) {
    if (t.label.empty()) return;
    if (t.exponent.empty())
      svg_.text(x, y, t.label, kTickFont, anchor, css);
    else
      svg_.power(x, y, t.label, t.exponent, kTickFont, anchor, css);
  }

  void labels() {
    const double bottom = layout_.top + layout_.height;
    const double x_label_y = bottom + 6.0 + (categorical() ? layout_.category_depth : kTickFont + 4.0) + 8.0 + kLabelFont;
    svg_.text(layout_.left + layout_.width / 2.0, x_label_y, axisTitle(panel_.x), kLabelFont, Anchor::middle,
              "axis-label x");
    svg_.text(layout_.box_x + 8.0 + kLabelFont, layout_.top + layout_.height / 2.0, axisTitle(panel_.y), kLabelFont,
              Anchor::middle, "axis-label y", -90.0);
    if (panel_.title.empty()) return;
    const double room = layout_.box_x + layout_.box_w - 8.0 - (layout_.box_x + 8.0);
    const double font = std::max(9.0, std::min(kTitleFont, kTitleFont * room / textWidth(panel_.title, kTitleFont)));
    svg_.text(layout_.box_x + 8.0, layout_.box_y + 8.0 + kTitleFont, fitted(panel_.title, room, font), font,
              Anchor::start, "panel-title");
  }

  void heatMap() {
    if (!panel_.heat_map) return;
    const HeatMap& map = *panel_.heat_map;
    const Mapping mx = xMap(), my = yMap();
    const Mapping colour{colour_ticks_.low, colour_ticks_.high, 0.0, 1.0, map.scale == Scale::log10};
    for (int r = 0; r < map.rows; ++r)
      for (int c = 0; c < map.columns; ++c) {
        const double v = map.values[static_cast<std::size_t>(r) * map.columns + c];
        if (!std::isfinite(v) || (map.scale == Scale::log10 && !(v > 0.0))) continue;
        const double x0 = mx(map.x0 + c * map.cell_width), x1 = mx(map.x0 + (c + 1) * map.cell_width);
        const double y0 = my(map.y0 + r * map.cell_height), y1 = my(map.y0 + (r + 1) * map.cell_height);
        // A quarter pixel of overlap hides the seams browsers leave between abutting cells.
        svg_.rect(std::min(x0, x1), std::min(y0, y1), std::abs(x1 - x0) + 0.25, std::abs(y1 - y0) + 0.25,
                  viridis(colour(v)), "none", "cell");
      }
  }

  void colourBar() {
    if (!panel_.heat_map) return;
    const HeatMap& map = *panel_.heat_map;
    const double x = layout_.left + layout_.width + 10.0, w = 14.0;
    const Mapping m{colour_ticks_.low, colour_ticks_.high, layout_.top + layout_.height, layout_.top,
                    map.scale == Scale::log10};
    constexpr int kSteps = 64;
    for (int k = 0; k < kSteps; ++k) {
      const double y0 = layout_.top + layout_.height * (kSteps - k - 1) / kSteps;
      svg_.rect(x, y0, w, layout_.height / kSteps + 0.25, viridis((k + 0.5) / kSteps), "none", "colour-bar");
    }
    svg_.rect(x, layout_.top, w, layout_.height, "none", "#444");
    double widest = 0.0;
    for (const auto& t : colour_ticks_.ticks) {
      const double y = m(t.value);
      svg_.line(x + w, y, x + w + (t.major ? 4.0 : 2.0), y, "#444", 1.0, "tick colour");
      label(t, x + w + 5.0, y + 0.35 * kTickFont, Anchor::start, "tick-label colour");
      widest = std::max(widest, tickLabelWidth(t));
    }
    Axis axis;
    axis.label = map.label, axis.unit = map.unit;
    svg_.text(x + w + 5.0 + widest + 8.0 + kLabelFont, layout_.top + layout_.height / 2.0, axisTitle(axis), kLabelFont,
              Anchor::middle, "axis-label colour", -90.0);
  }

  void bands() {
    const Mapping mx = xMap(), my = yMap();
    for (const auto& b : panel_.bands) {
      std::string points;
      for (std::size_t i = 0; i < b.x.size(); ++i)
        points += coordinate(mx(b.x[i])) + "," + coordinate(my(b.high[i])) + " ";
      for (std::size_t i = b.x.size(); i-- > 0;)
        points += coordinate(mx(b.x[i])) + "," + coordinate(my(b.low[i])) + " ";
      if (!b.x.empty()) svg_.polyline(points, "none", b.colour, 0.0, "band", 0.18);
    }
  }

  void references() {
    const Mapping my = yMap();
    for (const auto& r : panel_.references)
      svg_.line(layout_.left, my(r.value), layout_.left + layout_.width, my(r.value), r.colour, 1.0, "reference",
                r.dashed ? "5 3" : "");
  }

  std::size_t barSeriesCount() const {
    return static_cast<std::size_t>(std::count_if(panel_.series.begin(), panel_.series.end(),
                                                  [](const Series& s) { return s.mark == Mark::bars; }));
  }

  void bars() {
    const std::size_t groups = barSeriesCount();
    if (groups == 0) return;
    const Mapping mx = xMap(), my = yMap();
    const double slot =
        categorical() ? layout_.width / static_cast<double>(panel_.categories.size()) : layout_.width / 20.0;
    const double bar = 0.8 * slot / static_cast<double>(groups);
    const bool log = panel_.y.scale == Scale::log10;
    const double base = log ? layout_.top + layout_.height : my(std::clamp(0.0, y_ticks_.low, y_ticks_.high));
    std::size_t g = 0;
    for (std::size_t i = 0; i < panel_.series.size(); ++i) {
      const Series& s = panel_.series[i];
      if (s.mark != Mark::bars) continue;
      for (std::size_t k = 0; k < s.y.size(); ++k) {
        if (!std::isfinite(s.y[k]) || (log && !(s.y[k] > 0.0))) continue;
        const double x = mx(s.x[k]) - 0.4 * slot + (static_cast<double>(g) + 0.5) * bar;
        const double y = my(s.y[k]);
        svg_.rect(x - bar / 2.0 + 0.5, std::min(y, base), bar - 1.0, std::abs(base - y), colours_[i], "none", "bar");
        errorBar(s, k, x, my);
      }
      ++g;
    }
  }

  void errorBar(const Series& s, std::size_t k, double x, const Mapping& my) {
    if (s.sigma.empty() || !(s.sigma[k] > 0.0) || !std::isfinite(s.sigma[k])) return;
    const bool log = panel_.y.scale == Scale::log10;
    const double low = log ? std::max(s.y[k] - s.sigma[k], y_ticks_.low) : s.y[k] - s.sigma[k];
    const double y0 = my(low), y1 = my(s.y[k] + s.sigma[k]);
    svg_.line(x, y0, x, y1, "#222", 1.2, "error-bar");
    svg_.line(x - 3.0, y0, x + 3.0, y0, "#222", 1.2, "error-cap");
    svg_.line(x - 3.0, y1, x + 3.0, y1, "#222", 1.2, "error-cap");
  }

  void lines() {
    const Mapping mx = xMap(), my = yMap();
    const auto drawable = [this](double x, double y) {
      return std::isfinite(x) && std::isfinite(y) && (panel_.x.scale != Scale::log10 || x > 0.0) &&
             (panel_.y.scale != Scale::log10 || y > 0.0);
    };
    for (std::size_t i = 0; i < panel_.series.size(); ++i) {
      const Series& s = panel_.series[i];
      if (s.mark == Mark::bars) continue;
      if (s.mark != Mark::points) {
        std::string points;  // a gap at a value that cannot be drawn
        for (std::size_t k = 0; k <= s.x.size(); ++k) {
          if (k < s.x.size() && drawable(s.x[k], s.y[k])) {
            points += coordinate(mx(s.x[k])) + "," + coordinate(my(s.y[k])) + " ";
            continue;
          }
          if (!points.empty()) svg_.polyline(points, colours_[i], "none", 1.6, "series-line");
          points.clear();
        }
      }
      const double r = s.x.size() > 300 ? 1.6 : 2.6;
      for (std::size_t k = 0; k < s.x.size(); ++k) {
        if (!drawable(s.x[k], s.y[k])) continue;
        if (s.mark != Mark::line) svg_.circle(mx(s.x[k]), my(s.y[k]), r, colours_[i], "point");
        errorBar(s, k, mx(s.x[k]), my);
      }
    }
  }

  void vectors() {
    if (!panel_.vectors) return;
    const VectorField& field = *panel_.vectors;
    const Mapping mx = xMap(), my = yMap();
    for (std::size_t i = 0; i < field.sets.size(); ++i) {
      const VectorSet& v = field.sets[i];
      for (std::size_t k = 0; k < v.x.size(); ++k) {
        const double x0 = mx(v.x[k]), y0 = my(v.y[k]);
        const double x1 = mx(v.x[k] + field.magnification * v.dx[k]), y1 = my(v.y[k] + field.magnification * v.dy[k]);
        svg_.line(x0, y0, x1, y1, vector_colours_[i], 1.0, "vector");
        svg_.circle(x0, y0, 1.1, vector_colours_[i], "vector-base");
      }
    }
  }

  // The scale arrow: a round length of the true vectors, drawn at the figure's magnification.
  LegendEntry scaleArrow() const {
    const VectorField& field = *panel_.vectors;
    const Mapping mx = xMap();
    const double px_per_unit = std::abs(mx(1.0) - mx(0.0)) * field.magnification;
    const double length = nice125(50.0 / std::max(px_per_unit, 1e-300));
    char text[96];
    std::snprintf(text, sizeof text, "%g %s (arrows \xC3\x97%g)", length, field.unit.c_str(), field.magnification);
    return {LegendEntry::Kind::arrow, text, "#222", false, length * px_per_unit};
  }

  void legend() {
    std::vector<LegendEntry> entries = legend_;
    if (panel_.vectors) entries.push_back(scaleArrow());
    const double bottom = layout_.top + layout_.height;
    const double first_row = bottom + 6.0 + (categorical() ? layout_.category_depth : kTickFont + 4.0) + 8.0 +
                             kLabelFont + 4.0 + kLegendRow - 4.0;
    // The legend spans the panel's box, not only the plot area (narrow panels of many legs).
    const double start = layout_.box_x + 8.0, end = layout_.box_x + layout_.box_w - 8.0;
    double x = start, y = first_row;
    for (const auto& e : entries) {
      const double w = entryWidth(e);
      if (x > start && x + w > end) x = start, y += kLegendRow;
      swatch(e, x, y - 4.0);
      const double swatch_w = e.kind == LegendEntry::Kind::arrow ? e.arrow_length : 18.0;
      svg_.text(x + swatch_w + 5.0, y, fitted(e.label, end - (x + swatch_w + 5.0), kTickFont), kTickFont, Anchor::start,
                "legend");
      x += w;
    }
  }

  void swatch(const LegendEntry& e, double x, double y) {
    switch (e.kind) {
      case LegendEntry::Kind::box:
        svg_.rect(x + 3.0, y - 5.0, 12.0, 10.0, e.colour, "none", "legend-swatch");
        break;
      case LegendEntry::Kind::band:
        svg_.polyline(coordinate(x) + "," + coordinate(y - 5.0) + " " + coordinate(x + 18.0) + "," +
                          coordinate(y - 5.0) + " " + coordinate(x + 18.0) + "," + coordinate(y + 5.0) + " " +
                          coordinate(x) + "," + coordinate(y + 5.0),
                      "none", e.colour, 0.0, "legend-swatch", 0.3);
        break;
      case LegendEntry::Kind::point:
        svg_.circle(x + 9.0, y, 3.0, e.colour, "legend-swatch");
        break;
      case LegendEntry::Kind::arrow:
        svg_.line(x, y, x + e.arrow_length, y, e.colour, 1.5, "scale-arrow");
        svg_.polyline(coordinate(x + e.arrow_length - 6.0) + "," + coordinate(y - 3.5) + " " +
                          coordinate(x + e.arrow_length) + "," + coordinate(y) + " " +
                          coordinate(x + e.arrow_length - 6.0) + "," + coordinate(y + 3.5),
                      e.colour, e.colour, 1.0, "scale-arrow-head");
        break;
      default:
        svg_.line(x, y, x + 18.0, y, e.colour, 2.0, "legend-swatch", e.dashed ? "5 3" : "");
    }
  }

  SvgWriter& svg_;
  const Panel& panel_;
  std::string clip_id_;
  Layout layout_;
  TickSet x_ticks_, y_ticks_, colour_ticks_;
  std::vector<std::string> colours_, vector_colours_;
  std::vector<LegendEntry> legend_;
  int legend_rows_ = 0;
};

}  // namespace

std::string renderSvg(const Figure& figure, const std::string& id) {
  const int columns = std::max(1, figure.columns);
  const int rows = static_cast<int>((figure.panels.size() + columns - 1) / columns);
  const double title_height = figure.title.empty() ? 0.0 : 26.0;
  SvgWriter svg(columns * figure.panel_width, title_height + std::max(rows, 1) * figure.panel_height);
  if (!figure.title.empty())
    svg.text(8.0, 18.0, fitted(figure.title, columns * figure.panel_width - 16.0, 14.0), 14.0, Anchor::start,
             "figure-title");
  int legend_rows = 0;  // the most any panel needs, reserved in all
  for (const Panel& panel : figure.panels) {
    SvgWriter scratch(figure.panel_width, figure.panel_height);
    const PanelRenderer sizing(scratch, panel, "", 0.0, 0.0, figure.panel_width, figure.panel_height);
    legend_rows = std::max(legend_rows, sizing.legendRowCount());
  }
  for (std::size_t k = 0; k < figure.panels.size(); ++k) {
    const double x = static_cast<double>(k % columns) * figure.panel_width;
    const double y = title_height + static_cast<double>(k / columns) * figure.panel_height;
    PanelRenderer(svg, figure.panels[k], id + "-clip" + std::to_string(k), x, y, figure.panel_width,
                  figure.panel_height, legend_rows)
        .render();
  }
  return svg.str();
}

}  // namespace mire::report
