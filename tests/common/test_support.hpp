#pragma once
// Helpers shared by the test suites.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace mire::test {

// ../shared/ beside the checkout (external datasets with published results).
inline std::filesystem::path sharedDir() { return MIRE_SHARED_DIR; }
inline std::filesystem::path sourceDir() { return MIRE_SOURCE_DIR; }
inline std::filesystem::path mireBinary() { return MIRE_BINARY; }

// A fresh empty folder under the system's temporary directory, removed by the destructor.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline TempDir::TempDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "mire";
  for (char& c : name)
    if (c == '/') c = '_';
  path_ = std::filesystem::temp_directory_path() / ("mire-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}
inline TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

// Runs a shell command; returns its exit code (or -1 if it did not exit normally).
int runCommand(const std::string& command);

}  // namespace mire::test

// Skips the current test when ../shared/<relative> is absent.
#define MIRE_REQUIRE_SHARED(relative)                                                          \
  do {                                                                                         \
    if (!std::filesystem::exists(::mire::test::sharedDir() / (relative)))                      \
      GTEST_SKIP() << "needs ../shared/" << (relative) << " (external data), absent: skipped"; \
  } while (0)

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

namespace mire::test {
// Runs a shell command with stderr merged into stdout; returns the output and sets the exit code.
inline std::string captureCommand(const std::string& command, int* exit_code) {
  std::string output;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return output;
  char buffer[512];
  while (fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int status = pclose(pipe);
  *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return output;
}
}  // namespace mire::test

namespace mire::test {
// The whole content of a file, byte for byte ("" when it cannot be read).
inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The message of the std::runtime_error that `work()` throws, or "" when it throws none.
template <class Work>
std::string runtimeErrorOf(const Work& work) {
  try {
    work();
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

// The message `f` throws (any std::exception), or "(no error)".
inline std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

// Runs `mire <args>` with its output in dir/stdout.txt and dir/stderr.txt; returns the exit code.
inline int runMireIn(const TempDir& dir, const std::string& args) {
  return runCommand(mireBinary().string() + " " + args + " > " + (dir.path() / "stdout.txt").string() + " 2> " +
                    (dir.path() / "stderr.txt").string());
}
}  // namespace mire::test

inline int mire::test::runCommand(const std::string& command) {
  const int status = std::system(command.c_str());
  if (status == -1 || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}
