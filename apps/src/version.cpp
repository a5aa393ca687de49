#include "commands.hpp"

namespace mire::app {
std::string versionString() { return std::string("mire ") + MIRE_VERSION; }
}  // namespace mire::app
