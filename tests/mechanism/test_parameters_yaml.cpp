// Mechanism parameter files on the YAML layer: any YAML syntax in, plain YAML out (PyYAML
// reads it); missing parameters, degrees for radians, unknown and duplicate keys are errors
// naming the file, the line and the key.
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/io.hpp"

#include "test_support.hpp"

#include <cstdio>
#include <fstream>

namespace mire::mechanism {
namespace {

void write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string applyError(const std::filesystem::path& path, const std::vector<std::string>& may_default = {}) {
  try {
    ParameterSet p = h4Model12Parameters(H4Nominal{});
    applyParameterFile(readParameterFile(path), p, {}, may_default);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

const char* kFull =
    "R: 0.22\nL: 0.30\nl: 0.70\nh: 0.075\nd: 0.10\nalpha1: 0.785\nalpha2: 2.356\nalpha3: 3.927\nalpha4: 5.498\n"
    "q01: 0\nq02: 0\nq03: 0\nq04: 0\n";

TEST(ParameterYaml, EmptyOrPartialFilesAreErrorsNamingTheMissingParameters) {
  const test::TempDir dir;
  const auto path = dir.path() / "nominal.yaml";
  write(path, "");
  EXPECT_EQ(applyError(path), path.string() + ": empty file (expected a map of keys)");
  write(path, "# only a comment\n");
  EXPECT_EQ(applyError(path), path.string() + ": empty file (expected a map of keys)");
  write(path, "R: 0.22\n");
  const std::string partial = applyError(path);
  EXPECT_EQ(partial.rfind(path.string() + ":1: missing parameters 'L, l, h, d, alpha1", 0), 0u) << partial;
  // A caller may let named parameters keep their defaults.
  write(path, std::string(kFull).substr(0, std::string(kFull).find("q01")));
  EXPECT_NE(applyError(path).find("missing parameters 'q01, q02, q03, q04'"), std::string::npos);
  EXPECT_EQ(applyError(path, {"q01", "q02", "q03", "q04"}), "(no error)");
  write(path, kFull);
  EXPECT_EQ(applyError(path), "(no error)");
}

TEST(ParameterYaml, AnglesBeyondATurnSuggestDegrees) {
  const test::TempDir dir;
  const auto path = dir.path() / "nominal.yaml";
  std::string text = kFull;
  text.replace(text.find("alpha1: 0.785"), 13, "alpha1: 45");
  write(path, text);
  EXPECT_EQ(applyError(path),
            path.string() +
                ":6: key 'alpha1': 45 rad is more than a turn: angles are in radians (if you meant 45 "
                "degrees, write 0.785398)");
  text = kFull;
  text.replace(text.find("q03: 0"), 6, "q03: -7");
  write(path, text);
  EXPECT_NE(applyError(path).find(":12: key 'q03': -7 rad is more than a turn"), std::string::npos);
  // Lengths are not angles: 45 m is accepted here (the model's own checks judge it).
  text = kFull;
  text.replace(text.find("R: 0.22"), 7, "R: 6.5");
  write(path, text);
  EXPECT_EQ(applyError(path), "(no error)");
}

TEST(ParameterYaml, UnknownAndDuplicateKeysNameTheLine) {
  const test::TempDir dir;
  const auto path = dir.path() / "p.yaml";
  write(path, std::string(kFull) + "alpah2: 1\n");
  EXPECT_EQ(applyError(path), path.string() + ":14: unknown parameter name 'alpah2' (did you mean 'alpha2'?)");
  write(path, std::string(kFull) + "R: 0.23\n");
  EXPECT_EQ(applyError(path), path.string() + ":14: key 'R' appears twice (first at line 1)");
  write(path, std::string(kFull) + "sigma_R: [1, 2]\n");
  EXPECT_EQ(applyError(path),
            path.string() + ":14: key 'sigma_R': expected a single value (a number, or text for metadata)");
  write(path, std::string(kFull) + "sigma_R: -1\n");
  EXPECT_EQ(applyError(path), path.string() + ":14: key 'sigma_R': negative standard deviation");
}

TEST(ParameterYaml, AnyYamlSyntaxReads) {
  const test::TempDir dir;
  const auto path = dir.path() / "p.yaml";
  write(path,
        "{R: 0.22, L: 3.0e-1, l: .70, h: 0.075, d: 0.1, alpha1: 0.785, alpha2: 2.356, alpha3: 3.927, "
        "alpha4: 5.498, q01: 0, q02: 0, q03: 0, q04: +0.0, model: h4-12 # text\n}\n");
  ParameterSet p = h4Model12Parameters(H4Nominal{});
  applyParameterFile(readParameterFile(path), p);
  EXPECT_EQ(p.value("L"), 0.3);
  EXPECT_EQ(p.value("l"), 0.7);
}

TEST(ParameterYaml, PyYamlReadsTheFilesMireWrites) {
  if (test::runCommand("/usr/bin/python3 -c 'import yaml' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "needs python3-yaml (Debian), absent: skipped";
  const test::TempDir dir;
  const auto path = dir.path() / "identified.yaml";
  ParameterSet parameters = h4Model12Parameters(H4Nominal{});
  parameters.setValue("h", 1e-5);
  Eigen::VectorXd sigma = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(parameters.size()), 2.5e-7);
  writeParameterFile(path, parameters, sigma, {{"model", "h4-12 \"quoted\""}, {"variant", "D"}},
                     "a comment\non two lines");
  // Every number is a float for PyYAML (YAML 1.1), equal to the value written.
  const std::string command =
      "/usr/bin/python3 -c \"import yaml,sys; d=yaml.safe_load(open(sys.argv[1])); "
      "print(d['model'], d['h'] == 1e-5, d['sigma_R'] == 2.5e-7, all(isinstance(v, float) for k, v in d.items() "
      "if k not in ('model', 'variant')))\" " +
      path.string();
  int code = -1;
  const std::string out = test::captureCommand(command, &code);
  EXPECT_EQ(code, 0) << out;
  EXPECT_EQ(out, "h4-12 \"quoted\" True True True\n");
  ParameterSet back = h4Model12Parameters(H4Nominal{});
  applyParameterFile(readParameterFile(path), back);
  EXPECT_EQ(back.values(), parameters.values());
}

}  // namespace
}  // namespace mire::mechanism
