// Mechanism helpers shared by every model (joint columns, motion type names).
#include "mire/mechanism/mechanism.hpp"

namespace mire::mechanism {

std::string motionTypeName(MotionType type) {
  switch (type) {
    case MotionType::Schoenflies:
      return "schoenflies";
    case MotionType::Translation:
      return "translation";
    case MotionType::Spatial:
      return "spatial";
  }
  return "?";
}

std::vector<std::string> Mechanism::jointColumnNames() const {
  std::vector<std::string> names;
  const std::vector<Unit> units = jointUnits();
  for (std::size_t i = 0; i < units.size(); ++i)
    names.push_back("q" + std::to_string(i + 1) + "_" + unitName(units[i]));
  return names;
}

}  // namespace mire::mechanism
