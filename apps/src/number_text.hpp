#pragma once
// One number as report text (Markdown, report.html, terminal), shared by every command's report.
#include <string>

namespace mire::app {

std::string format(const char* pattern, double value);  // printf-style, one number
std::string fixed(double value, int digits);            // "n/a" when not finite

}  // namespace mire::app
