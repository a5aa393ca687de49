// mire::support's YAML layer: every syntax variant reads alike; every error names file, line, key.
#include "mire/support/yaml.hpp"
#include "test_support.hpp"

#include <cmath>
#include <fstream>
#include <limits>

namespace {
using mire::support::YamlError;
using mire::support::YamlFile;
using mire::support::YamlRange;

constexpr YamlRange kAny{-1e300, 1e300};

std::string errorOf(const std::string& text, void (*use)(const YamlFile&)) {
  try {
    use(YamlFile::parse(text, "f.yaml"));
  } catch (const YamlError& e) {
    return e.what();
  }
  return "(no error)";
}

// The same content in each syntax a user or another tool may write.
const char* kVariants[] = {
    "name: board\ncols: 9\nscale: 0.025\nmatrix: [1, 2, 3, 4]\n",
    "---\nname: board\ncols: 9\nscale: 0.025\nmatrix: [1, 2, 3, 4]\n",
    "%YAML 1.2\n---\nname: board\ncols: 9\nscale: 0.025\nmatrix: [1, 2, 3, 4]\n...\n",
    "%YAML:1.0\n---\nname: board\ncols: 9\nscale: 2.5e-2\nmatrix: !!opencv-matrix\n  rows: 1\n  cols: 4\n  dt: d\n"
    "  data: [ 1., 2., 3., 4. ]\n",
    "name: board\r\ncols: 9\r\nscale: 0.025\r\nmatrix: [1, 2, 3, 4]\r\n",
    "{name: board, cols: 9, scale: 0.025, matrix: [1, 2, 3, 4]}\n",
    "\xEF\xBB\xBFname: board\ncols: 9\nscale: 0.025\nmatrix: [1, 2, 3, 4]\n",
    "# a comment\nname: board  # the target\ncols: 9 # squares\n# between\nscale: 0.025 #m\nmatrix:  # list\n"
    "  - 1\n  - 2\n  - 3  # three\n  - 4\n# end\n",
    "name: 'board'\ncols: 0x9\nscale: +25e-3\nmatrix: [[1, 2, 3, 4]]\n",
};

TEST(Yaml, EveryVariantReadsTheSameValues) {
  for (const char* text : kVariants) {
    SCOPED_TRACE(text);
    const auto file = YamlFile::parse(text, "v.yaml");
    const auto& root = file.rootMap();
    root.checkKeys({"name", "cols", "scale", "matrix"});
    EXPECT_EQ(root.string("name"), "board");
    EXPECT_EQ(root.integer("cols", 1, 100), 9);
    EXPECT_DOUBLE_EQ(root.number("scale", {0, 1}), 0.025);
    const auto m = root.at("matrix").asMatrix(kAny);
    ASSERT_EQ(m.rows * m.cols, 4);
    EXPECT_EQ(m.data, (std::vector<double>{1, 2, 3, 4}));
  }
}

TEST(Yaml, LoadsFromDiskWithLineNumbers) {
  mire::test::TempDir dir;
  const auto path = dir.path() / "t.yaml";
  std::ofstream(path, std::ios::binary) << "a: 1\r\n\r\nb:\r\n  c: x\r\n";
  const auto file = YamlFile::load(path);
  try {
    file.rootMap().at("b").number("c", kAny);
    FAIL();
  } catch (const YamlError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ":4: key 'b.c': 'x' is not a number");
  }
}

TEST(Yaml, OutOfRangeIntegerPrintsTheValueAsWritten) {
  const auto message =
      errorOf("type: chess\n\n\ncols: 3000000000\n", [](const YamlFile& f) { f.rootMap().integer("cols", 1, 10000); });
  EXPECT_EQ(message, "f.yaml:4: key 'cols': 3000000000 is out of range (1..10000)");
}

TEST(Yaml, RangeErrorsUseSixSignificantDigits) {
  const auto message = errorOf("x: 1e308\n", [](const YamlFile& f) {
    f.rootMap().number("x", {0, std::numeric_limits<double>::max()});
    f.rootMap().number("x", {0, 1});
  });
  EXPECT_EQ(message, "f.yaml:1: key 'x': 1e+308 is out of range (0..1)");
  EXPECT_LT(message.size(), 60u);  // no 309-digit DBL_MAX
}

TEST(Yaml, NonFiniteAndNonNumbersAreRejected) {
  for (const char* bad : {".inf", "-.Inf", ".nan", "1e999", "12abc", "nan", "inf", "", "[1]", "0x"}) {
    SCOPED_TRACE(bad);
    const auto message =
        errorOf(std::string("x: ") + bad + "\n", [](const YamlFile& f) { f.rootMap().number("x", kAny); });
    EXPECT_EQ(message.rfind("f.yaml:1: key 'x': ", 0), 0u) << message;
  }
  EXPECT_EQ(errorOf("x: 2.5\n", [](const YamlFile& f) { f.rootMap().integer("x", 0, 9); }),
            "f.yaml:1: key 'x': '2.5' is not an integer");
}

TEST(Yaml, NumberSyntaxes) {
  const auto file = YamlFile::parse("a: 1.\nb: .5\nc: -1.5E+2\nd: 0o17\ne: 0x1F\nf: 8.0\ng: +3\n", "n.yaml");
  const auto& r = file.rootMap();
  EXPECT_EQ(r.number("a", kAny), 1.0);
  EXPECT_EQ(r.number("b", kAny), 0.5);
  EXPECT_EQ(r.number("c", kAny), -150.0);
  EXPECT_EQ(r.integer("d", 0, 100), 15);
  EXPECT_EQ(r.integer("e", 0, 100), 31);
  EXPECT_EQ(r.integer("f", 0, 100), 8);
  EXPECT_EQ(r.integer("g", 0, 100), 3);
}

TEST(Yaml, DuplicateKeysAreErrorsAtAnyDepth) {
  EXPECT_EQ(errorOf("a: 1\nb: 2\na: 3\n", [](const YamlFile&) {}), "f.yaml:3: key 'a' appears twice (first at line 1)");
  EXPECT_EQ(errorOf("m:\n  - {x: 1, x: 2}\n", [](const YamlFile&) {}),
            "f.yaml:2: key 'm[0].x' appears twice (first at line 2)");
}

TEST(Yaml, UnknownKeySuggestsTheClosest) {
  EXPECT_EQ(errorOf("noise: 1\n\nnosie: 2\n",
                    [](const YamlFile& f) {
                      f.rootMap().checkKeys({"noise", "seed"});
                    }),
            "f.yaml:3: unknown key 'nosie' (did you mean 'noise'?)");
  EXPECT_EQ(errorOf("zzzzzz: 1\n",
                    [](const YamlFile& f) {
                      f.rootMap().checkKeys({"noise", "seed"});
                    }),
            "f.yaml:1: unknown key 'zzzzzz' (known keys: noise seed)");
}

TEST(Yaml, MissingKeysEmptyFilesAndSyntaxErrors) {
  EXPECT_EQ(errorOf("a: 1\n", [](const YamlFile& f) { f.rootMap().at("b"); }), "f.yaml:1: missing key 'b'");
  EXPECT_EQ(errorOf("", [](const YamlFile& f) { f.rootMap(); }), "f.yaml: empty file (expected a map of keys)");
  EXPECT_EQ(errorOf("# only a comment\n---\n", [](const YamlFile& f) { f.rootMap(); }),
            "f.yaml: empty file (expected a map of keys)");
  EXPECT_EQ(errorOf("- 1\n- 2\n", [](const YamlFile& f) { f.rootMap(); }), "f.yaml:1: expected a map of keys");
  const auto syntax = errorOf("a: [1, 2\nb: 3\n", [](const YamlFile&) {});
  EXPECT_EQ(syntax.rfind("f.yaml:", 0), 0u) << syntax;
  EXPECT_NE(syntax.find("invalid YAML"), std::string::npos) << syntax;
  const auto two = errorOf("a: 1\n---\nb: 2\n", [](const YamlFile&) {});
  EXPECT_NE(two.find("second YAML document"), std::string::npos) << two;
  EXPECT_EQ(errorOf("m:\n  rows: 2\n  cols: 2\n  dt: d\n  data: [1, 2, 3]\n",
                    [](const YamlFile& f) { f.rootMap().at("m").asMatrix(kAny); }),
            "f.yaml:5: key 'm.data': has 3 numbers, rows x cols = 4");
}

TEST(Yaml, MissingFileAndFolderAreErrors) {
  mire::test::TempDir dir;
  EXPECT_THROW(YamlFile::load(dir.path() / "absent.yaml"), YamlError);
  EXPECT_THROW(YamlFile::load(dir.path()), YamlError);
}

TEST(Yaml, FormattedNumbersRoundTripAndAreFloatsForYaml11) {
  for (double v : {0.0, 1.0, -2.5, 1e-5, 123456789.123, 1e20, 0.1, 6.02214076e23, -3e-300}) {
    const std::string text = mire::support::formatYamlNumber(v);
    SCOPED_TRACE(text);
    EXPECT_NE(text.find('.'), std::string::npos);
    const auto e = text.find('e');
    if (e != std::string::npos) {
      EXPECT_TRUE(text[e + 1] == '+' || text[e + 1] == '-');
    }
    const auto file = YamlFile::parse("v: " + text + "\n", "n.yaml");
    EXPECT_EQ(file.rootMap().number("v", kAny), v);
  }
  EXPECT_EQ(mire::support::formatMessageNumber(std::numeric_limits<double>::max()), "1.79769e+308");
}

TEST(Yaml, DeepNestingIsAnErrorNotACrash) {
  const std::string deep = "a: " + std::string(200, '[') + std::string(200, ']') + "\n";
  EXPECT_THROW(YamlFile::parse(deep, "deep.yaml"), YamlError);
}

// yaml-cpp 0.7 loops forever on a node that starts a line with ',' outside a flow collection
// (found by the fuzz targets; the inputs are kept in fuzz/corpus/*/regression-hang-*). mire
// refuses such a line before yaml-cpp sees it, naming the line; valid uses of ',' still read.
// Debian's yaml-cpp 0.7 loops forever on some malformed texts (fuzz/corpus/*/regression-hang-*);
// libyaml's syntax pass refuses them first, with the line.
TEST(Yaml, MalformedTextIsRefusedWithItsLineNotAHang) {
  const auto parseOnly = [](const YamlFile&) {};
  for (const auto& [text, line] :
       std::vector<std::pair<std::string, int>>{{",a\n", 1},
                                                {"# c\n---\n,\n", 3},
                                                {"  ,\n", 1},
                                                {"    a: 3\n  , 3\n", 2},
                                                {"# identified\n,ode|: h4-12\nvariant: D\n", 2},
                                                {"a: !tag,\n", 1},
                                                {"a: {{{\n,\n", 2},
                                                {"a: [1,\n ,2]\n", 2}}) {
    const std::string error = errorOf(text, parseOnly);
    EXPECT_NE(error.find("f.yaml:" + std::to_string(line) + ": invalid YAML: "), std::string::npos)
        << text << " -> " << error;
  }
  for (const std::string text : {"a: [1\n  , 2]\n", "note: |\n  , hello\nb: 1\n", "a: \"x,\ny\"\n",
                                 "name: it's\nb: 1\n", "a: {b: 1\n  , c: 2}\n", "%YAML 1.2\n---\na: 1\n"})
    EXPECT_EQ(errorOf(text, parseOnly), "(no error)") << text;
}

// A text yaml-cpp 0.7 looped on and libyaml reads (an anchored plain scalar): an answer, not a hang.
TEST(Yaml, TextYamlCppLoopedOnIsRead) {
  const auto file = YamlFile::parse("&L:%\n, .\n\n", "f.yaml");
  EXPECT_EQ(file.root().asString(), ":% , .");  // anchor "L"
}

TEST(Yaml, AliasesShareTheirAnchorAndCannotLoop) {
  const auto file = YamlFile::parse("a: &x [1, 2]\nb: *x\n", "f.yaml");
  EXPECT_EQ(file.rootMap().at("b").asDoubles({0, 10}), (std::vector<double>{1, 2}));
  const std::string self = errorOf("a: &x [1, *x]\n", [](const YamlFile&) {});
  EXPECT_NE(self.find("f.yaml:1: invalid YAML: alias '*x'"), std::string::npos) << self;
  std::string laughs = "a: &a [x, x, x, x, x, x, x, x, x, x]\n";
  for (char c = 'b'; c <= 'j'; ++c)
    laughs += std::string(1, c) + ": &" + c + " [*" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" +
              char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) +
              ", *" + char(c - 1) + ", *" + char(c - 1) + "]\n";
  const std::string expanded = errorOf(laughs, [](const YamlFile&) {});
  EXPECT_NE(expanded.find("too many nodes"), std::string::npos) << expanded;
}

TEST(Yaml, TextThatIsNotUtf8IsRefusedWithItsLine) {
  const std::string error = errorOf("a: 1\n# cam\xe9ra\n", [](const YamlFile&) {});
  EXPECT_NE(error.find("f.yaml:2: invalid YAML: "), std::string::npos) << error;
  EXPECT_NE(error.find("UTF-8"), std::string::npos) << error;
}

}  // namespace
