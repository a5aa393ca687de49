#include "yaml_tree.hpp"

#include <yaml.h>

#include <algorithm>
#include <unordered_map>

#include "mire/support/yaml.hpp"

namespace mire::support::detail {

namespace {

// RAII owners of libyaml's C structs.
class Parser {
 public:
  explicit Parser(const std::string& text) {
    if (!yaml_parser_initialize(&parser_)) throw YamlError("libyaml: cannot initialise a parser (out of memory)");
    yaml_parser_set_input_string(&parser_, reinterpret_cast<const unsigned char*>(text.data()), text.size());
  }
  ~Parser() { yaml_parser_delete(&parser_); }
  Parser(const Parser&) = delete;
  Parser& operator=(const Parser&) = delete;
  yaml_parser_t* get() { return &parser_; }

 private:
  yaml_parser_t parser_{};
};

struct Event {
  yaml_event_t event{};
  Event() = default;
  ~Event() { yaml_event_delete(&event); }
  Event(const Event&) = delete;
  Event& operator=(const Event&) = delete;
};

std::string text(const yaml_char_t* chars) { return chars ? reinterpret_cast<const char*>(chars) : ""; }

// A reader error (bytes that are not UTF-8, control characters) has no mark, only the byte
// offset: libyaml decodes ahead of its parser.
yaml_mark_t errorMark(const yaml_parser_t& parser, const std::string& input) {
  if (parser.error != YAML_READER_ERROR) return parser.problem_mark;
  yaml_mark_t mark{};
  const std::size_t end = std::min(parser.problem_offset, input.size());
  for (std::size_t i = 0; i < end; ++i) {
    if (input[i] == '\n') {
      ++mark.line, mark.column = 0;
    } else {
      ++mark.column;
    }
  }
  return mark;
}

// libyaml's words, with the one a user meets most made plain.
std::string problemText(const yaml_parser_t& parser) {
  std::string problem = parser.problem ? parser.problem : "syntax error";
  if (problem.find("UTF-8") != std::string::npos) problem += " (mire reads YAML files as UTF-8)";
  if (parser.context) problem += std::string(" ") + parser.context;
  return problem;
}

// A plain, untagged scalar that YAML reads as null (as yaml-cpp did: "", ~, null, Null, NULL).
bool isNullScalar(const yaml_event_t& event) {
  const auto& scalar = event.data.scalar;
  if (scalar.style != YAML_PLAIN_SCALAR_STYLE || !scalar.plain_implicit) return false;
  const std::string value(reinterpret_cast<const char*>(scalar.value), scalar.length);
  return value.empty() || value == "~" || value == "null" || value == "Null" || value == "NULL";
}

// Builds the documents from the event stream with an explicit stack of open collections.
class TreeBuilder {
 public:
  TreeBuilder(const std::string& name, YamlTreeLimits limits) : name_(name), limits_(limits) {}

  // False at the end of the stream.
  bool add(const yaml_event_t& event) {
    switch (event.type) {
      case YAML_STREAM_END_EVENT:
        return false;
      case YAML_DOCUMENT_START_EVENT:
        startDocument();
        break;
      case YAML_DOCUMENT_END_EVENT:
        endDocument(event.start_mark);
        break;
      case YAML_ALIAS_EVENT:
        alias(event);
        break;
      case YAML_SCALAR_EVENT:
        scalar(event);
        break;
      case YAML_SEQUENCE_START_EVENT:
        open(event, YamlTreeNode::Kind::Sequence, event.data.sequence_start.anchor, event.data.sequence_start.tag);
        break;
      case YAML_MAPPING_START_EVENT:
        open(event, YamlTreeNode::Kind::Map, event.data.mapping_start.anchor, event.data.mapping_start.tag);
        break;
      case YAML_SEQUENCE_END_EVENT:
      case YAML_MAPPING_END_EVENT:
        close();
        break;
      default:
        break;
    }
    return true;
  }

  std::vector<YamlTreePtr> documents;

 private:
  struct Open {
    std::shared_ptr<YamlTreeNode> node;
    std::string anchor;
    YamlTreePtr key;  // a map's key waiting for its value
  };

  [[noreturn]] void fail(const yaml_mark_t& mark, const std::string& what) const {
    throw YamlError(name_ + ":" + std::to_string(mark.line + 1) + ": invalid YAML: " + what);
  }

  std::shared_ptr<YamlTreeNode> make(const yaml_event_t& event, YamlTreeNode::Kind kind, const yaml_char_t* tag) {
    if (++nodes_ > limits_.max_nodes)
      fail(event.start_mark, "more than " + std::to_string(limits_.max_nodes) + " values (not a mire file)");
    auto node = std::make_shared<YamlTreeNode>();
    node->kind = kind;
    node->tag = text(tag);
    node->line = static_cast<int>(event.start_mark.line) + 1;
    return node;
  }

  void startDocument() {
    root_.reset();
    anchors_.clear();  // anchors are local to a document
  }

  void endDocument(const yaml_mark_t& mark) {
    if (!root_) {
      auto empty = std::make_shared<YamlTreeNode>();
      empty->line = static_cast<int>(mark.line) + 1;
      root_ = empty;
    }
    documents.push_back(root_);
  }

  void attach(const YamlTreePtr& node) {
    if (open_.empty()) {
      root_ = node;
      return;
    }
    Open& parent = open_.back();
    if (parent.node->kind == YamlTreeNode::Kind::Sequence) {
      parent.node->items.push_back(node);
    } else if (!parent.key) {
      parent.key = node;
    } else {
      parent.node->entries.emplace_back(std::move(parent.key), node);
      parent.key.reset();
    }
  }

  void remember(const yaml_char_t* anchor, const YamlTreePtr& node) {
    if (anchor) anchors_[text(anchor)] = node;
  }

  void scalar(const yaml_event_t& event) {
    const auto& data = event.data.scalar;
    auto node = make(event, isNullScalar(event) ? YamlTreeNode::Kind::Null : YamlTreeNode::Kind::Scalar, data.tag);
    if (node->kind == YamlTreeNode::Kind::Scalar)
      node->text.assign(reinterpret_cast<const char*>(data.value), data.length);
    remember(data.anchor, node);
    attach(node);
  }

  void alias(const yaml_event_t& event) {
    const std::string anchor = text(event.data.alias.anchor);
    const auto it = anchors_.find(anchor);
    if (it == anchors_.end())
      fail(event.start_mark, "alias '*" + anchor + "' names no complete anchored node before it");
    attach(it->second);
  }

  void open(const yaml_event_t& event, YamlTreeNode::Kind kind, const yaml_char_t* anchor, const yaml_char_t* tag) {
    if (static_cast<int>(open_.size()) >= limits_.max_depth)
      fail(event.start_mark, "nested more than " + std::to_string(limits_.max_depth) + " levels deep");
    open_.push_back({make(event, kind, tag), text(anchor), nullptr});
  }

  // The anchor is registered only now: an alias inside its own node is an error, not a cycle.
  void close() {
    Open done = std::move(open_.back());
    open_.pop_back();
    if (!done.anchor.empty()) anchors_[done.anchor] = done.node;
    attach(done.node);
  }

  const std::string& name_;
  YamlTreeLimits limits_;
  std::size_t nodes_ = 0;
  std::vector<Open> open_;
  std::unordered_map<std::string, YamlTreePtr> anchors_;
  YamlTreePtr root_;
};

}  // namespace

std::vector<YamlTreePtr> parseYamlDocuments(const std::string& text, const std::string& name, YamlTreeLimits limits) {
  Parser parser(text);
  TreeBuilder builder(name, limits);
  for (;;) {
    Event event;
    if (!yaml_parser_parse(parser.get(), &event.event)) {
      const yaml_mark_t mark = errorMark(*parser.get(), text);
      throw YamlError(name + ":" + std::to_string(mark.line + 1) + ": invalid YAML: " + problemText(*parser.get()) +
                      " (column " + std::to_string(mark.column + 1) + ")");
    }
    if (!builder.add(event.event)) break;
  }
  return std::move(builder.documents);
}

}  // namespace mire::support::detail
