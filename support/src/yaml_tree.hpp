#pragma once
// The parsed form of a YAML text (support/src/yaml.cpp reads it through YamlNode). Built from the
// events of libyaml, the reference C parser: linear in the input, no recursion on nesting, and it
// reports the line and column of the first syntax error. mire used yaml-cpp before; Debian's
// yaml-cpp 0.7 loops forever on some malformed texts (found by the fuzz targets of fuzz/,
// doc/robustness.md), which no guard in front of it could rule out.
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace mire::support::detail {

struct YamlTreeNode {
  enum class Kind { Null, Scalar, Sequence, Map };
  Kind kind = Kind::Null;  // Null: an empty value, or a plain ~ / null / Null / NULL
  std::string tag;         // as libyaml resolves it ("tag:yaml.org,2002:opencv-matrix"), "" if none
  std::string text;        // a scalar's value
  int line = 1;            // 1-based line where the node starts
  std::vector<std::shared_ptr<const YamlTreeNode>> items;  // a sequence's items
  std::vector<std::pair<std::shared_ptr<const YamlTreeNode>, std::shared_ptr<const YamlTreeNode>>> entries;  // a map's
};

using YamlTreePtr = std::shared_ptr<const YamlTreeNode>;

// Bounds checked while parsing, before memory is spent on an absurd input.
struct YamlTreeLimits {
  int max_depth;          // nested collections
  std::size_t max_nodes;  // nodes built (an alias is not a copy)
};

// Every document of the text (an empty document is a Null node). An alias shares its anchor's
// node (a DAG: an alias to a node not yet complete is an error, so no cycle). Throws YamlError
// "name:line: invalid YAML: <problem> (column c)" on the first syntax error, on text that is not
// UTF-8, and past the limits.
std::vector<YamlTreePtr> parseYamlDocuments(const std::string& text, const std::string& name, YamlTreeLimits limits);

}  // namespace mire::support::detail
