#include "mire/support/input_file.hpp"

#include <sys/stat.h>

#include <stdexcept>
#include <string>

namespace mire::support {

void requireRegularFile(const std::filesystem::path& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw std::runtime_error(path.string() + ": no such file");
  if (S_ISREG(info.st_mode)) return;
  std::string kind = "not a regular file";
  if (S_ISDIR(info.st_mode)) kind = "a folder";
  if (S_ISFIFO(info.st_mode)) kind = "a FIFO (named pipe)";
  if (S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode)) kind = "a device";
  if (S_ISSOCK(info.st_mode)) kind = "a socket";
  throw std::runtime_error(path.string() + ": is " + kind + ", a regular file is expected");
}

}  // namespace mire::support
