#pragma once
// A minimal SVG element writer: absolute coordinates (no group transforms, so a test can read
// every element's position as written), XML-escaped text, numbers with two decimals.
#include <string>
#include <string_view>

namespace mire::report {

// &, <, >, " and ' as entities; control characters other than tab and newline dropped (not XML).
std::string escapeXml(std::string_view text);

// The width a label takes in the sans-serif face of the figures, estimated at 0.6 em per
// character (wider than the average glyph of Helvetica/DejaVu Sans, so boxes built with it
// over- rather than under-estimate); layout and the overlap tests both use it.
double textWidth(std::string_view text, double font_size);

enum class Anchor { start, middle, end };

class SvgWriter {
 public:
  SvgWriter(double width, double height);
  void rect(double x, double y, double w, double h, const std::string& fill, const std::string& stroke = "none",
            const std::string& css_class = "");
  void line(double x0, double y0, double x1, double y1, const std::string& stroke, double width = 1.0,
            const std::string& css_class = "", const std::string& dash = "");
  void circle(double x, double y, double r, const std::string& fill, const std::string& css_class = "");
  // `points` as "x,y x,y ..."; closed and filled when `fill` is not "none".
  void polyline(const std::string& points, const std::string& stroke, const std::string& fill, double width = 1.5,
                const std::string& css_class = "", double opacity = 1.0);
  // Text at (x, y) on its baseline; `rotate` −90 reads bottom to top, turned about (x, y).
  void text(double x, double y, std::string_view content, double font_size, Anchor anchor = Anchor::start,
            const std::string& css_class = "", double rotate = 0.0, const std::string& fill = "#222");
  // A base with a raised exponent (log-axis labels "10⁻³"); the pair is one <text>.
  void power(double x, double y, std::string_view base, std::string_view exponent, double font_size, Anchor anchor,
             const std::string& css_class = "");
  void beginClip(const std::string& id, double x, double y, double w, double h);
  void endClip();
  void raw(std::string_view markup);
  std::string str() const;

 private:
  std::string body_;
  double width_, height_;
};

// "12.34" with at most two decimals and no trailing zeros: coordinates in the markup.
std::string coordinate(double value);

}  // namespace mire::report
