#pragma once
// Outputs are written atomically: to a temporary file beside the target, then renamed,
// so an interrupted run never leaves a truncated result behind.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace mire::support {

// Writes `contents` to `path` atomically. Throws std::runtime_error naming the path.
void writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

// Calls `writer(temporary_path)`, which must create that file (e.g. cv::imwrite), then
// renames it onto `path`. The temporary keeps the target's extension so writers that pick
// the format from it still work. Throws std::runtime_error naming the path if the writer
// fails or returns false.
void writeAtomically(const std::filesystem::path& path, const std::function<bool(const std::filesystem::path&)>& writer);

}  // namespace mire::support
