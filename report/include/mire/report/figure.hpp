#pragma once
// Figures for reports as SVG (doc/plots.md): panels with linear or log axes, nice ticks and
// tick labels, axis labels with units, line / point / bar series with ±σ error bars, σ bands,
// reference lines, legends naming only what is drawn, residual vector fields over an image frame
// with a scale arrow stating the magnification, and heat maps with a colour bar. Rendering is
// pure text: no image drawing, every coordinate absolute so tests can check the geometry.
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mire::report {

enum class Scale { linear, log10 };

struct Axis {
  std::string label, unit;  // drawn as "label (unit)"; unit empty: dimensionless
  Scale scale = Scale::linear;
  std::optional<double> min, max;  // fixed ends; else the data's range widened to nice ticks
  bool include_zero = false;       // linear: the range reaches 0 (bars, magnitudes)
  bool symmetric = false;          // linear: the range is ±max|value| (residuals)
  bool tight = false;              // the range is exactly [min, max], ticks inside it only (image frames)
  bool inverted = false;           // y grows downward (image rows)
};

inline Axis makeAxis(std::string label, std::string unit = "", Scale scale = Scale::linear) {
  Axis axis;
  axis.label = std::move(label), axis.unit = std::move(unit), axis.scale = scale;
  return axis;
}

enum class Mark { line, points, line_points, bars };

// x: the abscissae, or the category indices 0…n−1 when the panel has categories (bars).
struct Series {
  std::string label;  // empty: not in the legend
  Mark mark = Mark::line_points;
  std::vector<double> x, y;
  std::vector<double> sigma;  // ±σ error bar per point; empty: none; NaN or ≤ 0: none at that point
  std::string colour;         // empty: the palette's next colour
};

// A shaded band between low and high along x (a ±σ or ±2σ band).
struct Band {
  std::string label;
  std::vector<double> x, low, high;
  std::string colour = "#1f77b4";
};

// A horizontal line across the panel at y = value (zero, a threshold).
struct ReferenceLine {
  double value = 0.0;
  std::string label;  // in the legend when not empty
  std::string colour = "#555";
  bool dashed = true;
};

// Vectors from (x, y) to (x + m·dx, y + m·dy), m the field's magnification.
struct VectorSet {
  std::string label;
  std::vector<double> x, y, dx, dy;
  std::string colour;
};

struct VectorField {
  std::vector<VectorSet> sets;
  double magnification = 1.0;  // drawn length / true length
  std::string unit;            // of dx, dy ("px"); the scale arrow states it
};

// Cell values on a regular grid (row-major, rows along y), coloured by a viridis scale drawn as
// a colour bar on the panel's right; non-finite cells are left blank.
struct HeatMap {
  int columns = 0, rows = 0;
  double x0 = 0.0, y0 = 0.0, cell_width = 1.0, cell_height = 1.0;
  std::vector<double> values;
  std::string label, unit;  // of the colour bar
  Scale scale = Scale::linear;
};

struct Panel {
  std::string title;
  Axis x, y;
  std::vector<std::string> categories;  // bar labels along x (x then holds indices)
  std::vector<Series> series;
  std::vector<Band> bands;
  std::vector<ReferenceLine> references;
  std::optional<VectorField> vectors;
  std::optional<HeatMap> heat_map;
  bool equal_aspect = false;  // one x unit as long as one y unit (image frames)
};

struct Figure {
  std::string title;  // above the panels; empty: none (the report's caption says it)
  std::vector<Panel> panels;
  int columns = 1;
  double panel_width = 460.0, panel_height = 300.0;  // each panel's box, axes and labels included
};

// The figure as an <svg> element; `id` prefixes its clip-path ids (unique within one page).
// Throws std::invalid_argument when a series' lengths disagree or a log axis meets no positive value.
std::string renderSvg(const Figure& figure, const std::string& id = "fig");

// The 1-2-5 × 10^k value nearest to `value` (> 0): scale arrows, magnifications.
double nice125(double value);

// Colours: the categorical palette (10, Tableau) and viridis for t in [0, 1] as "#rrggbb".
const std::string& paletteColour(std::size_t index);
std::string viridis(double t);

}  // namespace mire::report
