#include "commands.hpp"

#include <iostream>

namespace mire::app {
Runner addSimulateCommand(CLI::App& app) {
  app.add_subcommand("simulate", "(not implemented yet)");
  return [] {
    std::cerr << "mire simulate: not implemented yet\n";
    return static_cast<int>(kUsage);
  };
}
}  // namespace mire::app
