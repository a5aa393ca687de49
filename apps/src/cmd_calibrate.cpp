#include "commands.hpp"

#include <iostream>

namespace mire::app {
Runner addCalibrateCommand(CLI::App& app) {
  app.add_subcommand("calibrate", "(not implemented yet)");
  return [] {
    std::cerr << "mire calibrate: not implemented yet\n";
    return static_cast<int>(kUsage);
  };
}
}  // namespace mire::app
