#include "mire/support/yaml.hpp"

#include "yaml_tree.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace mire::support {

namespace {

// Larger inputs are not mire files; refusing them keeps a mistaken path from costing memory.
constexpr std::uintmax_t kMaxFileBytes = 64u << 20;
// Bounds on nesting, on nodes built and on nodes visited (aliases can multiply them) at load.
constexpr int kMaxDepth = 64;
constexpr std::size_t kMaxNodes = 1'000'000;
constexpr std::size_t kMaxVisits = 2'000'000;

using detail::YamlTreeNode;
using Kind = YamlTreeNode::Kind;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return {};
  const auto end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

// OpenCV writes "%YAML:1.0", which YAML parsers reject; blank it (keeping line numbers).
std::string normalise(std::string text) {
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  if (text.compare(0, 6, "%YAML:") == 0) {
    const auto end = text.find('\n');
    text.replace(0, end == std::string::npos ? text.size() : end, "#");
  }
  return text;
}

struct DuplicateCheck {
  const std::string& file;
  std::size_t visits = 0;

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw YamlError(file + ":" + std::to_string(line) + ": " + what);
  }

  void walk(const YamlTreeNode& node, const std::string& path, int depth) {
    if (++visits > kMaxVisits) fail(node.line, "too many nodes (aliases expanding?)");
    if (depth > kMaxDepth) fail(node.line, "nested more than 64 levels deep");
    if (node.kind == Kind::Sequence) {
      std::size_t i = 0;
      for (const auto& item : node.items) walk(*item, path + "[" + std::to_string(i++) + "]", depth + 1);
    } else if (node.kind == Kind::Map) {
      walkMap(node, path, depth);
    }
  }

  void walkMap(const YamlTreeNode& node, const std::string& path, int depth) {
    std::unordered_map<std::string, int> seen;
    for (const auto& [key_node, value] : node.entries) {
      if (key_node->kind != Kind::Scalar) fail(key_node->line, "a key must be a plain name, not a map or a list");
      const std::string& key = key_node->text;
      const std::string full = path.empty() ? key : path + "." + key;
      const auto [it, inserted] = seen.emplace(key, key_node->line);
      if (!inserted)
        fail(key_node->line, "key '" + full + "' appears twice (first at line " + std::to_string(it->second) + ")");
      walk(*value, full, depth + 1);
    }
  }
};

// Unsigned digits in a base (YAML 1.2 0x.. and 0o.. integers); false on bad syntax.
bool parseBased(const std::string& digits, int base, double& value) {
  if (digits.empty()) return false;
  std::uint64_t parsed = 0;
  const auto result = std::from_chars(digits.data(), digits.data() + digits.size(), parsed, base);
  if (result.ptr != digits.data() + digits.size()) return false;
  value = result.ec == std::errc::result_out_of_range ? std::numeric_limits<double>::infinity()
                                                      : static_cast<double>(parsed);
  return true;
}

// A number in YAML 1.2 / YAML 1.1 / OpenCV syntax, or nullopt when the text is not one.
std::optional<double> parseNumber(const std::string& raw) {
  std::string text = trim(raw);
  if (text.empty()) return std::nullopt;
  double sign = 1.0;
  if (text[0] == '+' || text[0] == '-') {
    sign = text[0] == '-' ? -1.0 : 1.0;
    text.erase(0, 1);
  }
  const std::string low = lower(text);
  if (low == ".inf") return sign * std::numeric_limits<double>::infinity();
  if (low == ".nan" && sign > 0) return std::numeric_limits<double>::quiet_NaN();
  double value = 0.0;
  if (low.compare(0, 2, "0x") == 0)
    return parseBased(low.substr(2), 16, value) ? std::optional(sign * value) : std::nullopt;
  if (low.compare(0, 2, "0o") == 0)
    return parseBased(low.substr(2), 8, value) ? std::optional(sign * value) : std::nullopt;
  if (text.empty() || !(std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '.')) return std::nullopt;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value, std::chars_format::general);
  if (result.ptr != text.data() + text.size()) return std::nullopt;
  if (result.ec == std::errc::result_out_of_range) {
    // Overflow reads as infinite (and is reported so); underflow as zero.
    value = std::abs(std::strtod(text.c_str(), nullptr)) > 1.0 ? std::numeric_limits<double>::infinity() : 0.0;
  }
  return sign * value;
}

// Optimal string alignment distance (a transposition counts one), case-insensitive.
std::size_t editDistance(const std::string& a_in, const std::string& b_in) {
  const std::string a = lower(a_in), b = lower(b_in);
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

std::string rangeText(YamlRange range) {
  return "(" + formatMessageNumber(range.min) + ".." + formatMessageNumber(range.max) + ")";
}

}  // namespace

// ---------------------------------------------------------------- YamlFile

YamlFile YamlFile::load(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw YamlError(name + ": file not found");
  if (!std::filesystem::is_regular_file(path, ec)) throw YamlError(name + ": not a regular file");
  const auto bytes = std::filesystem::file_size(path, ec);
  if (!ec && bytes > kMaxFileBytes)
    throw YamlError(name + ": " + std::to_string(bytes) + " bytes is too large for a YAML file (at most 64 MiB)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw YamlError(name + ": cannot open for reading");
  std::ostringstream content;
  content << in.rdbuf();
  return parse(content.str(), name);
}

YamlFile YamlFile::parse(const std::string& raw_text, const std::string& name) {
  std::string text = normalise(raw_text);
  const auto documents = detail::parseYamlDocuments(text, name, {kMaxDepth, kMaxNodes});
  YamlNode::Tree root;
  for (const auto& document : documents) {
    if (document->kind == Kind::Null) continue;
    if (root)
      throw YamlError(name + ":" + std::to_string(document->line) +
                      ": a second YAML document ('---'); a mire file holds one");
    root = document;
  }
  if (!root) root = std::make_shared<const YamlTreeNode>();
  DuplicateCheck{name}.walk(*root, "", 0);
  return YamlFile(YamlNode(root, name, "", root->line), std::move(text));
}

const YamlNode& YamlFile::rootMap() const {
  if (root_.isNull()) throw YamlError(root_.file() + ": empty file (expected a map of keys)");
  root_.requireMap();
  return root_;
}

// ---------------------------------------------------------------- YamlNode: basics

std::string YamlNode::where() const { return file_ + ":" + std::to_string(line_); }

void YamlNode::fail(const std::string& what) const {
  if (key_.empty()) throw YamlError(where() + ": " + what);
  throw YamlError(where() + ": key '" + key_ + "': " + what);
}

bool YamlNode::isMap() const { return node_->kind == Kind::Map; }
bool YamlNode::isSequence() const { return node_->kind == Kind::Sequence; }
bool YamlNode::isScalar() const { return node_->kind == Kind::Scalar; }
bool YamlNode::isNull() const { return node_->kind == Kind::Null; }
std::string YamlNode::tag() const { return node_->tag; }

YamlNode YamlNode::child(const Tree& node, const std::string& key, int key_line) const {
  // A scalar's line is its own; an empty value has none, and a nested map or list starts on the
  // next line: the key's line is where a reader looks.
  const int line = node->kind == Kind::Scalar ? node->line : key_line;
  return YamlNode(node, file_, key, line);
}

void YamlNode::requireMap() const {
  if (isMap()) return;
  fail(isNull() ? "expected a map of keys, found an empty value" : "expected a map of keys");
}

// ---------------------------------------------------------------- maps

std::optional<YamlNode> YamlNode::find(const std::string& key) const {
  requireMap();
  for (const auto& [key_node, value] : node_->entries) {
    if (key_node->kind == Kind::Scalar && key_node->text == key) {
      const std::string path = key_.empty() ? key : key_ + "." + key;
      return child(value, path, key_node->line);
    }
  }
  return std::nullopt;
}

bool YamlNode::has(const std::string& key) const { return find(key).has_value(); }

YamlNode YamlNode::at(const std::string& key) const {
  auto found = find(key);
  if (!found) {
    const std::string path = key_.empty() ? key : key_ + "." + key;
    throw YamlError(where() + ": missing key '" + path + "'");
  }
  return *found;
}

std::optional<YamlNode> YamlNode::findAny(const std::vector<std::string>& keys) const {
  for (const auto& key : keys)
    if (auto found = find(key)) return found;
  return std::nullopt;
}

std::vector<std::string> YamlNode::keys() const {
  requireMap();
  std::vector<std::string> names;
  for (const auto& entry : node_->entries) names.push_back(entry.first->text);
  return names;
}

void YamlNode::checkKeys(const std::vector<std::string>& known) const {
  requireMap();
  for (const auto& entry : node_->entries) {
    const std::string& key = entry.first->text;
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    const std::string path = key_.empty() ? key : key_ + "." + key;
    const std::string hint = closestName(key, known);
    std::string message = file_ + ":" + std::to_string(entry.first->line) + ": unknown key '" + path + "'";
    if (!hint.empty()) {
      message += " (did you mean '" + hint + "'?)";
    } else {
      message += " (known keys:";
      for (const auto& name : known) message += " " + name;
      message += ")";
    }
    throw YamlError(message);
  }
}

std::optional<double> YamlNode::optionalNumber(const std::string& key, YamlRange range) const {
  auto found = find(key);
  if (!found || found->isNull()) return std::nullopt;
  return found->asDouble(range);
}

// ---------------------------------------------------------------- sequences

std::size_t YamlNode::size() const { return isSequence() ? node_->items.size() : isMap() ? node_->entries.size() : 0; }

std::vector<YamlNode> YamlNode::items() const {
  if (!isSequence()) fail(isNull() ? "expected a list, found an empty value" : "expected a list");
  std::vector<YamlNode> result;
  result.reserve(node_->items.size());
  for (std::size_t i = 0; i < node_->items.size(); ++i) result.push_back((*this)[i]);
  return result;
}

YamlNode YamlNode::operator[](std::size_t index) const {
  if (!isSequence()) fail("expected a list");
  const std::size_t count = node_->items.size();
  if (index >= count) fail("has " + std::to_string(count) + " items, item " + std::to_string(index) + " asked");
  const Tree& item = node_->items[index];
  // An empty item has no line of its own: the list's.
  return YamlNode(item, file_, key_ + "[" + std::to_string(index) + "]", item->kind == Kind::Null ? line_ : item->line);
}

// ---------------------------------------------------------------- scalars

std::string YamlNode::scalarText(const char* expected) const {
  if (isScalar()) return node_->text;
  if (isNull()) fail(std::string("missing value (expected ") + expected + ")");
  fail(std::string("expected ") + expected + ", found a " + (isMap() ? "map" : "list"));
}

std::string YamlNode::asString() const { return scalarText("text"); }

bool YamlNode::asBool() const {
  const std::string text = lower(trim(scalarText("true or false")));
  if (text == "true" || text == "yes" || text == "on") return true;
  if (text == "false" || text == "no" || text == "off") return false;
  fail("'" + text + "' is not true or false");
}

double YamlNode::asDouble(YamlRange range) const {
  const std::string text = trim(scalarText("a number"));
  const auto value = parseNumber(text);
  if (!value) fail("'" + text + "' is not a number");
  if (!std::isfinite(*value)) fail("'" + text + "' is not a finite number");
  if (*value < range.min || *value > range.max)
    fail(formatMessageNumber(*value) + " is out of range " + rangeText(range));
  return *value;
}

std::int64_t YamlNode::asInt(std::int64_t min, std::int64_t max) const {
  const std::string text = trim(scalarText("an integer"));
  const auto value = parseNumber(text);
  if (!value) fail("'" + text + "' is not a number");
  if (!std::isfinite(*value)) fail("'" + text + "' is not a finite number");
  if (*value != std::floor(*value)) fail("'" + text + "' is not an integer");
  const std::string bounds = "(" + std::to_string(min) + ".." + std::to_string(max) + ")";
  // Compare as doubles first: the value may exceed what an int64 holds.
  if (*value < static_cast<double>(min) || *value > static_cast<double>(max)) fail(text + " is out of range " + bounds);
  const auto integer = static_cast<std::int64_t>(*value);
  if (integer < min || integer > max) fail(text + " is out of range " + bounds);
  return integer;
}

std::vector<double> YamlNode::asDoubles(YamlRange range) const {
  std::vector<double> values;
  for (const auto& item : items()) values.push_back(item.asDouble(range));
  return values;
}

YamlMatrix YamlNode::asMatrix(YamlRange range) const {
  YamlMatrix matrix;
  if (isMap()) {  // OpenCV's !!opencv-matrix
    checkKeys({"rows", "cols", "dt", "data"});
    matrix.rows = static_cast<int>(integer("rows", 0, 100000));
    matrix.cols = static_cast<int>(integer("cols", 0, 100000));
    if (const auto dt_node = find("dt")) {  // OpenCV writes it; ROS camera_info does not
      const std::string dt = trim(dt_node->asString());
      if (dt.empty() || dt.find_first_not_of("1234567890ucswifdh") != std::string::npos)
        dt_node->fail("'" + dt + "' is not an OpenCV element type (u, c, w, s, i, f, d)");
    }
    matrix.data = at("data").asDoubles(range);
    const auto expected = static_cast<std::size_t>(matrix.rows) * static_cast<std::size_t>(matrix.cols);
    if (matrix.data.size() != expected)
      at("data").fail("has " + std::to_string(matrix.data.size()) + " numbers, rows x cols = " + std::to_string(expected));
    return matrix;
  }
  const auto rows = items();
  if (rows.empty()) return matrix;
  if (!rows.front().isSequence()) {
    matrix.data = asDoubles(range);
    matrix.rows = 1;
    matrix.cols = static_cast<int>(matrix.data.size());
    return matrix;
  }
  matrix.rows = static_cast<int>(rows.size());
  matrix.cols = static_cast<int>(rows.front().size());
  for (const auto& row : rows) {
    const auto values = row.asDoubles(range);
    if (values.size() != static_cast<std::size_t>(matrix.cols))
      row.fail("has " + std::to_string(values.size()) + " numbers, the first row " + std::to_string(matrix.cols));
    matrix.data.insert(matrix.data.end(), values.begin(), values.end());
  }
  return matrix;
}

// ---------------------------------------------------------------- formatting

std::optional<double> parseYamlNumber(const std::string& text) { return parseNumber(text); }

std::string yamlQuoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out + "\"";
}

std::string formatYamlNumber(double value) {
  if (std::isnan(value)) return ".nan";
  if (std::isinf(value)) return value > 0 ? ".inf" : "-.inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  std::string text(buffer, result.ptr);
  const auto e = text.find('e');
  std::string mantissa = e == std::string::npos ? text : text.substr(0, e);
  std::string exponent = e == std::string::npos ? "" : text.substr(e + 1);
  if (mantissa.find('.') == std::string::npos) mantissa += ".0";
  if (!exponent.empty() && exponent[0] != '-' && exponent[0] != '+') exponent = "+" + exponent;
  return exponent.empty() ? mantissa : mantissa + "e" + exponent;
}

std::string formatMessageNumber(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  return buffer;
}

std::string closestName(const std::string& name, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& candidate : candidates) {
    const std::size_t distance = editDistance(name, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  const std::size_t allowed = std::max<std::size_t>(2, name.size() / 3);
  return best_distance <= allowed && best_distance < name.size() ? best : std::string();
}

}  // namespace mire::support
