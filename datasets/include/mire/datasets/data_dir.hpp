#pragma once
// Where the `mire` command finds the specs it reads at run time (the demo's camera and target,
// the H4 nominal geometry): a folder holding specs/*.yaml, never a path into the source checkout
// (doc/install.md "Data lookup").
#include <filesystem>
#include <string>

namespace mire::datasets {

// The data folder, first of:
//  1. $MIRE_DATA_DIR (an error when it is set but holds no specs/ folder);
//  2. <folder of the running executable>/../share/mire — the installed layout (bin/mire,
//     share/mire) and the build tree (<build>/apps/mire, <build>/share/mire, copied at build time);
//  3. the install location configured at build time (<prefix>/share/mire).
// Throws std::runtime_error naming every place it looked when none holds specs/.
std::filesystem::path dataDirectory();

// dataDirectory() / "specs" / name, e.g. specPath("h4_nominal.yaml").
std::filesystem::path specPath(const std::string& name);

}  // namespace mire::datasets
