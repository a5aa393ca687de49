// SVG element writer (see svg.hpp).
#include "mire/report/svg.hpp"

#include <cmath>
#include <cstdio>

namespace mire::report {

std::string escapeXml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        if (static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n') out += c;
    }
  }
  return out;
}

double textWidth(std::string_view text, double font_size) {
  std::size_t glyphs = 0;  // UTF-8: count lead bytes only (σ, ±, ² are one glyph)
  for (const char c : text)
    if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) ++glyphs;
  return 0.6 * font_size * static_cast<double>(glyphs);
}

std::string coordinate(double value) {
  if (!std::isfinite(value)) value = 0.0;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", value);
  std::string s = buffer;
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  if (s == "-0") s = "0";
  return s;
}

namespace {

std::string attribute(const char* name, const std::string& value) {
  return value.empty() ? std::string() : std::string(" ") + name + "=\"" + escapeXml(value) + "\"";
}

const char* anchorName(Anchor anchor) {
  switch (anchor) {
    case Anchor::middle:
      return "middle";
    case Anchor::end:
      return "end";
    default:
      return "start";
  }
}

}  // namespace

SvgWriter::SvgWriter(double width, double height) : width_(width), height_(height) {}

void SvgWriter::rect(double x, double y, double w, double h, const std::string& fill, const std::string& stroke,
                     const std::string& css_class) {
  body_ += "<rect x=\"" + coordinate(x) + "\" y=\"" + coordinate(y) + "\" width=\"" + coordinate(w) + "\" height=\"" +
           coordinate(h) + "\"" + attribute("fill", fill) + attribute("stroke", stroke) +
           attribute("class", css_class) + "/>\n";
}

void SvgWriter::line(double x0, double y0, double x1, double y1, const std::string& stroke, double width,
                     const std::string& css_class, const std::string& dash) {
  body_ += "<line x1=\"" + coordinate(x0) + "\" y1=\"" + coordinate(y0) + "\" x2=\"" + coordinate(x1) + "\" y2=\"" +
           coordinate(y1) + "\"" + attribute("stroke", stroke) + " stroke-width=\"" + coordinate(width) + "\"" +
           attribute("stroke-dasharray", dash) + attribute("class", css_class) + "/>\n";
}

void SvgWriter::circle(double x, double y, double r, const std::string& fill, const std::string& css_class) {
  body_ += "<circle cx=\"" + coordinate(x) + "\" cy=\"" + coordinate(y) + "\" r=\"" + coordinate(r) + "\"" +
           attribute("fill", fill) + attribute("class", css_class) + "/>\n";
}

void SvgWriter::polyline(const std::string& points, const std::string& stroke, const std::string& fill, double width,
                         const std::string& css_class, double opacity) {
  const bool closed = fill != "none";
  body_ += std::string(closed ? "<polygon" : "<polyline") + " points=\"" + points + "\"" + attribute("stroke", stroke) +
           " stroke-width=\"" + coordinate(width) + "\"" + attribute("fill", fill) +
           (opacity < 1.0 ? " opacity=\"" + coordinate(opacity) + "\"" : std::string()) +
           attribute("class", css_class) + " stroke-linejoin=\"round\"/>\n";
}

void SvgWriter::text(double x, double y, std::string_view content, double font_size, Anchor anchor,
                     const std::string& css_class, double rotate, const std::string& fill) {
  body_ +=
      "<text x=\"" + coordinate(x) + "\" y=\"" + coordinate(y) + "\" font-size=\"" + coordinate(font_size) +
      "\" text-anchor=\"" + anchorName(anchor) + "\"" + attribute("fill", fill) + attribute("class", css_class) +
      (rotate != 0.0 ? " transform=\"rotate(" + coordinate(rotate) + " " + coordinate(x) + " " + coordinate(y) + ")\""
                     : std::string()) +
      ">" + escapeXml(content) + "</text>\n";
}

void SvgWriter::power(double x, double y, std::string_view base, std::string_view exponent, double font_size,
                      Anchor anchor, const std::string& css_class) {
  body_ += "<text x=\"" + coordinate(x) + "\" y=\"" + coordinate(y) + "\" font-size=\"" + coordinate(font_size) +
           "\" text-anchor=\"" + anchorName(anchor) + "\" fill=\"#222\"" + attribute("class", css_class) + ">" +
           escapeXml(base) + "<tspan dy=\"-0.45em\" font-size=\"0.75em\">" + escapeXml(exponent) + "</tspan></text>\n";
}

void SvgWriter::beginClip(const std::string& id, double x, double y, double w, double h) {
  body_ += "<clipPath id=\"" + escapeXml(id) + "\"><rect x=\"" + coordinate(x) + "\" y=\"" + coordinate(y) +
           "\" width=\"" + coordinate(w) + "\" height=\"" + coordinate(h) + "\"/></clipPath>\n<g clip-path=\"url(#" +
           escapeXml(id) + ")\">\n";
}

void SvgWriter::endClip() { body_ += "</g>\n"; }

void SvgWriter::raw(std::string_view markup) { body_ += markup; }

std::string SvgWriter::str() const {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + coordinate(width_) + "\" height=\"" +
         coordinate(height_) + "\" viewBox=\"0 0 " + coordinate(width_) + " " + coordinate(height_) +
         "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n<rect x=\"0\" y=\"0\" width=\"" +
         coordinate(width_) + "\" height=\"" + coordinate(height_) + "\" fill=\"white\"/>\n" + body_ + "</svg>\n";
}

}  // namespace mire::report
