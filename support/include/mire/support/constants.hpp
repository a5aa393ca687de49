#pragma once
// Mathematical constants shared by the modules (one home instead of a copy per file; M_PI is
// POSIX, not standard C++17).

namespace mire::support {

constexpr double kPi = 3.14159265358979323846;

// Angle units: radians = degrees × kRadiansPerDegree, degrees = radians × kDegreesPerRadian.
constexpr double kRadiansPerDegree = kPi / 180.0;
constexpr double kDegreesPerRadian = 180.0 / kPi;

}  // namespace mire::support
