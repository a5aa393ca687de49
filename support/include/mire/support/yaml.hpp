#pragma once
// mire's one YAML reader (on libyaml, support/src/yaml_tree.hpp): standard YAML 1.2 with or without a %YAML directive,
// OpenCV FileStorage files (a "%YAML:1.0" first line, !!opencv-matrix nodes), "---"-only files,
// CRLF, a UTF-8 BOM, comments anywhere, flow style. Duplicate keys are errors (YAML parsers
// commonly keep one silently). Every getter validates strictly, and every error names the file, the line and
// the key: "target.yaml:4: key 'cols': 3000000000 is out of range (1..10000)". The file format
// rules are documented in doc/file-formats.md.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace mire::support {

namespace detail {
struct YamlTreeNode;
}

// Every YAML input error (parse, missing/unknown/duplicate key, type, range).
class YamlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A closed range for numbers read from a file; messages print its bounds with %.6g.
struct YamlRange {
  double min;
  double max;
};

// A numeric matrix read from YAML: an OpenCV "!!opencv-matrix" map (rows, cols, dt, data; dt
// optional, as ROS camera_info writes these maps without it), a
// flat sequence (one row), or a sequence of equal-length sequences. Row-major.
struct YamlMatrix {
  int rows = 0;
  int cols = 0;
  std::vector<double> data;
  double operator()(int r, int c) const {
    return data[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(c)];
  }
};

// One node of a loaded file, with its location (file, line) and its key path for messages.
// Cheap to copy (shares the parsed document).
class YamlNode {
 public:
  // Location for messages: "file:line" (line 1-based; the key's line for an empty value).
  std::string where() const;
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  // Key path of this node: "camera_matrix", "camera_matrix.data[3]", "" for the root.
  const std::string& key() const { return key_; }

  bool isMap() const;
  bool isSequence() const;
  bool isScalar() const;
  bool isNull() const;  // "~", "null", an empty value
  // The YAML tag as written, e.g. "tag:yaml.org,2002:opencv-matrix" for OpenCV's matrices.
  std::string tag() const;

  // ----- maps -----
  bool has(const std::string& key) const;  // throws if this node is not a map
  // The value of a key; throws "file:line: missing key 'k'" when absent.
  YamlNode at(const std::string& key) const;
  std::optional<YamlNode> find(const std::string& key) const;
  // The first of several accepted spellings present (e.g. {"camera_matrix", "cameraMatrix", "K"}).
  std::optional<YamlNode> findAny(const std::vector<std::string>& keys) const;
  std::vector<std::string> keys() const;  // in file order
  // Throws on the first key not in `known`, suggesting the closest known key:
  // "file:7: unknown key 'nosie' (did you mean 'noise'?)".
  void checkKeys(const std::vector<std::string>& known) const;
  // Throws unless this node is a map ("file:line: key 'k': expected a map of keys").
  void requireMap() const;

  // ----- sequences -----
  std::size_t size() const;                      // number of items (sequence) or keys (map); 0 for a scalar/null
  YamlNode operator[](std::size_t index) const;  // sequence item; throws out of range
  std::vector<YamlNode> items() const;           // sequence items; throws if not a sequence

  // ----- scalars (strict) -----
  std::string asString() const;  // any scalar, as written
  bool asBool() const;           // true/false (also yes/no/on/off as YAML 1.1 readers accept)
  // A finite number in any YAML/OpenCV syntax (1, -2.5, 1e-3, 1.5E+2, .5, 0x1F, 0o17);
  // rejects .inf/.nan and values outside the range.
  double asDouble(YamlRange range) const;
  // An integer (an integral-valued number such as 8 or 8.0 is accepted), within the range;
  // the message prints the value as written ("3000000000 is out of range (1..10000)").
  std::int64_t asInt(std::int64_t min, std::int64_t max) const;
  std::vector<double> asDoubles(YamlRange range) const;  // a sequence of numbers
  YamlMatrix asMatrix(YamlRange range) const;

  // ----- shorthands for a key of this map -----
  double number(const std::string& key, YamlRange range) const { return at(key).asDouble(range); }
  std::optional<double> optionalNumber(const std::string& key, YamlRange range) const;
  std::int64_t integer(const std::string& key, std::int64_t min, std::int64_t max) const {
    return at(key).asInt(min, max);
  }
  std::string string(const std::string& key) const { return at(key).asString(); }

  // Throws YamlError "file:line: key 'k': <what>" (or "file:line: <what>" at the root).
  [[noreturn]] void fail(const std::string& what) const;

 private:
  friend class YamlFile;
  using Tree = std::shared_ptr<const detail::YamlTreeNode>;
  YamlNode(Tree node, std::string file, std::string key, int line)
      : node_(std::move(node)), file_(std::move(file)), key_(std::move(key)), line_(line) {}
  YamlNode child(const Tree& node, const std::string& key, int key_line) const;
  std::string scalarText(const char* expected) const;

  Tree node_;  // never null (an absent value is a Null node)
  std::string file_;
  std::string key_;
  int line_ = 0;
};

// A loaded YAML file. Parse errors, a missing file and more than one document are YamlError
// naming the file and line; duplicate keys anywhere in the file are rejected at load.
class YamlFile {
 public:
  static YamlFile load(const std::filesystem::path& path);
  // Same rules, from text; `name` stands for the file name in messages.
  static YamlFile parse(const std::string& text, const std::string& name);

  // The document's root (null for an empty file); rootMap() also requires a map of keys
  // ("file: empty file" / "file:1: expected a map of keys").
  const YamlNode& root() const { return root_; }
  const YamlNode& rootMap() const;
  // The first lines of the text (after the BOM), to let readers detect a format.
  const std::string& text() const { return text_; }

 private:
  YamlFile(YamlNode root, std::string text) : root_(std::move(root)), text_(std::move(text)) {}
  YamlNode root_;
  std::string text_;
};

// A number formatted for YAML files people read: round-trips (17 significant digits, shortest
// form that reads back identically) and is a float for YAML 1.1 readers such as PyYAML too
// (always a '.' and a signed exponent: 1.0e-05, not 1e-05 which PyYAML reads as a string).
std::string formatYamlNumber(double value);

// A YAML scalar's text read as a number, as YamlNode::asDouble reads it (any YAML/OpenCV syntax;
// .inf/.nan read as non-finite values for the caller to refuse); nullopt if it is no number.
std::optional<double> parseYamlNumber(const std::string& text);

// Free text as a double-quoted YAML scalar (quotes and backslashes escaped, control characters
// dropped), for metadata and names in files mire writes.
std::string yamlQuoted(const std::string& text);

// A number for messages (%.6g), the project's convention.
std::string formatMessageNumber(double value);

// The closest candidate within a small edit distance, or "" (for "did you mean" hints).
std::string closestName(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace mire::support
