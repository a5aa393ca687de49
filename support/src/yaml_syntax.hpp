#pragma once
// The syntax pass of mire's YAML reader (support/src/yaml.cpp): libyaml, the reference C parser,
// reads the whole text once before yaml-cpp builds nodes. Why two parsers: Debian's yaml-cpp 0.7
// loops forever on some malformed inputs (found by the fuzz targets of fuzz/, doc/robustness.md);
// libyaml's event parser is linear in the input, keeps no recursion on nesting, and reports the
// line and column of the first syntax error. A text that passes is handed to yaml-cpp.
#include <string>

namespace mire::support {

// Throws YamlError "name:line: invalid YAML: <problem> (column c)" on the first syntax error, on
// text that is not UTF-8, and on collections nested deeper than max_depth.
void checkYamlSyntax(const std::string& text, const std::string& name, int max_depth);

}  // namespace mire::support
