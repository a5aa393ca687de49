#pragma once
// The check every reader of a user file makes before opening it (doc/robustness.md): a FIFO,
// a device or a socket would block or never end, so only an existing regular file is read.
// In the library, so that the Python readers refuse what the command refuses.
#include <filesystem>

namespace mire::support {

// Throws std::runtime_error "<path>: is a FIFO (named pipe), a regular file is expected" (or
// "no such file", "is a folder", "is a device", "is a socket").
void requireRegularFile(const std::filesystem::path& path);

}  // namespace mire::support
