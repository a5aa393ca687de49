// The `mire` command's contract: help, version, unknown subcommands.
#include "test_support.hpp"

#include <cstdio>
#include <memory>

namespace {}  // namespace

TEST(Cli, HelpListsEverySubcommand) {
  int code = -1;
  const std::string out = mire::test::captureCommand(mire::test::mireBinary().string() + " --help", &code);
  EXPECT_EQ(code, 0);
  for (const char* sub : {"calibrate", "measure", "identify", "simulate", "demo"})
    EXPECT_NE(out.find(sub), std::string::npos) << sub << " missing from:\n" << out;
}

TEST(Cli, VersionPrintsTheProjectVersion) {
  int code = -1;
  const std::string out = mire::test::captureCommand(mire::test::mireBinary().string() + " --version", &code);
  EXPECT_EQ(code, 0);
  EXPECT_NE(out.find("mire 0."), std::string::npos) << out;
}

TEST(Cli, UnknownSubcommandExitsTwoWithOneLine) {
  int code = -1;
  const std::string out = mire::test::captureCommand(mire::test::mireBinary().string() + " frobnicate", &code);
  EXPECT_EQ(code, 2);
  EXPECT_EQ(out.rfind("mire: ", 0), 0u) << out;
  EXPECT_NE(out.find("frobnicate"), std::string::npos) << out;
}
