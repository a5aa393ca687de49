#include "number_text.hpp"

#include <cmath>
#include <cstdio>

namespace mire::app {

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

std::string fixed(double value, int digits) {
  char pattern[16];
  std::snprintf(pattern, sizeof pattern, "%%.%df", digits);
  return std::isfinite(value) ? format(pattern, value) : "n/a";
}

}  // namespace mire::app
