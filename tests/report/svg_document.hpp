#pragma once
// An SVG (or XHTML) document parsed with expat, as a flat list of elements with their attributes
// and text: the figure tests read positions from it, and parsing at all proves well-formed XML.
#include <expat.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace mire::test {

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::string text;  // character data directly inside, tspans included
  double number(const std::string& key) const { return std::stod(attributes.at(key)); }
  bool hasClass(const std::string& css) const {
    const auto it = attributes.find("class");
    if (it == attributes.end()) return false;
    const std::string padded = " " + it->second + " ";
    return padded.find(" " + css + " ") != std::string::npos;
  }
};

class XmlDocument {
 public:
  // Throws std::runtime_error with expat's message and line when the text is not well-formed XML.
  explicit XmlDocument(const std::string& text) {
    XML_Parser parser = XML_ParserCreate("UTF-8");
    XML_SetUserData(parser, this);
    XML_SetElementHandler(parser, &XmlDocument::start, &XmlDocument::end);
    XML_SetCharacterDataHandler(parser, &XmlDocument::characters);
    const bool ok = XML_Parse(parser, text.data(), static_cast<int>(text.size()), 1) != XML_STATUS_ERROR;
    const std::string message = ok ? ""
                                   : std::string(XML_ErrorString(XML_GetErrorCode(parser))) + " at line " +
                                         std::to_string(XML_GetCurrentLineNumber(parser));
    XML_ParserFree(parser);
    if (!ok) throw std::runtime_error("not well-formed XML: " + message);
  }

  std::vector<XmlElement> elements;

  std::vector<const XmlElement*> withClass(const std::string& name, const std::string& css) const {
    std::vector<const XmlElement*> out;
    for (const auto& e : elements)
      if (e.name == name && e.hasClass(css)) out.push_back(&e);
    return out;
  }
  std::vector<const XmlElement*> named(const std::string& name) const {
    std::vector<const XmlElement*> out;
    for (const auto& e : elements)
      if (e.name == name) out.push_back(&e);
    return out;
  }

 private:
  static void start(void* self, const XML_Char* name, const XML_Char** attributes) {
    auto& doc = *static_cast<XmlDocument*>(self);
    XmlElement e;
    e.name = name;
    for (int i = 0; attributes[i]; i += 2) e.attributes[attributes[i]] = attributes[i + 1];
    if (e.name == "tspan" && !doc.open_.empty()) {  // part of its text's content
      doc.open_.push_back(doc.open_.back());
      return;
    }
    doc.elements.push_back(e);
    doc.open_.push_back(doc.elements.size() - 1);
  }
  static void end(void* self, const XML_Char*) { static_cast<XmlDocument*>(self)->open_.pop_back(); }
  static void characters(void* self, const XML_Char* text, int length) {
    auto& doc = *static_cast<XmlDocument*>(self);
    if (!doc.open_.empty()) doc.elements[doc.open_.back()].text.append(text, static_cast<std::size_t>(length));
  }
  std::vector<std::size_t> open_;
};

}  // namespace mire::test
