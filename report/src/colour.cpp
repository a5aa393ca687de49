// The figures' colours (see figure.hpp): a categorical palette and the viridis map.
#include "mire/report/figure.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace mire::report {

const std::string& paletteColour(std::size_t index) {
  static const std::array<std::string, 10> palette = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                                      "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  return palette[index % palette.size()];
}

std::string viridis(double t) {
  // viridis sampled at 0, 1/8, …, 1 (matplotlib's table), interpolated linearly in RGB.
  static const std::array<std::array<double, 3>, 9> anchors = {{{68, 1, 84},
                                                                {71, 44, 122},
                                                                {59, 81, 139},
                                                                {44, 113, 142},
                                                                {33, 144, 141},
                                                                {39, 173, 129},
                                                                {92, 200, 99},
                                                                {170, 220, 50},
                                                                {253, 231, 37}}};
  if (!std::isfinite(t)) t = 0.0;
  const double s = std::clamp(t, 0.0, 1.0) * 8.0;
  const auto k = std::min<std::size_t>(static_cast<std::size_t>(s), 7);
  const double f = s - static_cast<double>(k);
  char buffer[8];
  int rgb[3];
  for (int c = 0; c < 3; ++c) rgb[c] = static_cast<int>(std::lround(anchors[k][c] * (1.0 - f) + anchors[k + 1][c] * f));
  std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return buffer;
}

double nice125(double value) {
  if (!(value > 0.0) || !std::isfinite(value)) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  const double m = value / decade;
  return (m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0) * decade;
}

}  // namespace mire::report
