#include "yaml_syntax.hpp"

#include <yaml.h>

#include <algorithm>

#include "mire/support/yaml.hpp"

namespace mire::support {

namespace {

// RAII owners of libyaml's C structs.
struct Parser {
  yaml_parser_t parser{};
  Parser(const std::string& text) {
    if (!yaml_parser_initialize(&parser)) throw YamlError("libyaml: cannot initialise a parser (out of memory)");
    yaml_parser_set_input_string(&parser, reinterpret_cast<const unsigned char*>(text.data()), text.size());
  }
  ~Parser() { yaml_parser_delete(&parser); }
  Parser(const Parser&) = delete;
  Parser& operator=(const Parser&) = delete;
};

struct Event {
  yaml_event_t event{};
  ~Event() { yaml_event_delete(&event); }
};

[[noreturn]] void fail(const std::string& name, const yaml_mark_t& mark, const std::string& problem) {
  throw YamlError(name + ":" + std::to_string(mark.line + 1) + ": invalid YAML: " + problem + " (column " +
                  std::to_string(mark.column + 1) + ")");
}

// libyaml's words, with the two a user meets most made plain.
std::string problemText(const yaml_parser_t& parser) {
  std::string problem = parser.problem ? parser.problem : "syntax error";
  if (problem.find("UTF-8") != std::string::npos) problem += " (mire reads YAML files as UTF-8)";
  if (parser.context) problem += std::string(" ") + parser.context;
  return problem;
}

// A reader error (bytes that are not UTF-8, control characters) has no mark, only the byte offset:
// libyaml decodes ahead of its parser.
yaml_mark_t errorMark(const yaml_parser_t& parser, const std::string& text) {
  if (parser.error != YAML_READER_ERROR) return parser.problem_mark;
  yaml_mark_t mark{};
  const std::size_t end = std::min(parser.problem_offset, text.size());
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') ++mark.line, mark.column = 0;
    else ++mark.column;
  }
  return mark;
}

}  // namespace

void checkYamlSyntax(const std::string& text, const std::string& name, int max_depth) {
  Parser owner(text);
  int depth = 0;
  for (;;) {
    Event event;
    if (!yaml_parser_parse(&owner.parser, &event.event)) 
      fail(name, errorMark(owner.parser, text), problemText(owner.parser));
    switch (event.event.type) {
      case YAML_SEQUENCE_START_EVENT:
      case YAML_MAPPING_START_EVENT:
        if (++depth > max_depth)
          fail(name, event.event.start_mark, "nested more than " + std::to_string(max_depth) + " levels deep");
        break;
      case YAML_SEQUENCE_END_EVENT:
      case YAML_MAPPING_END_EVENT:
        --depth;
        break;
      case YAML_STREAM_END_EVENT:
        return;
      default:
        break;
    }
  }
}

}  // namespace mire::support
