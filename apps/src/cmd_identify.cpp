#include "commands.hpp"

#include <iostream>

namespace mire::app {
Runner addIdentifyCommand(CLI::App& app) {
  app.add_subcommand("identify", "(not implemented yet)");
  return [] {
    std::cerr << "mire identify: not implemented yet\n";
    return static_cast<int>(kUsage);
  };
}
}  // namespace mire::app
