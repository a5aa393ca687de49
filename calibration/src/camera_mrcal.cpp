// mrcal's .cameramodel, both ways (doc/file-formats.md "Camera files"): a Python literal
// (a dict with comments) holding 'lensmodel', 'intrinsics', 'extrinsics', 'imagersize' and
// optional keys mrcal adds ('optimization_inputs', 'valid_intrinsics_region', ...). mire reads
// LENSMODEL_PINHOLE and LENSMODEL_OPENCV4/5/8/12 (the same projection as mire's, same pixel
// convention) and refuses every other lens model by name. mrcal ignores keys it does not know,
// so mire keeps its covariance (and the camera's name, its RMS) there under mire_* keys.
#include "mire/calibration/camera_formats.hpp"

#include "mire/support/yaml.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace mire::calibration {
namespace {

// A value of the Python literal: a dict, a list (or tuple), a string, a number, or another
// constant (True, False, None).
struct PyValue {
  enum class Kind { Dict, List, String, Number, Constant };
  Kind kind = Kind::Constant;
  int line = 0;
  std::string text;  // String: its contents; Constant: its name
  double number = 0.0;
  std::vector<std::pair<std::string, PyValue>> entries;  // Dict
  std::vector<PyValue> items;                            // List
};

// Recursive-descent reader of the literal subset mrcal writes. Errors name the file and line.
class PyLiteralReader {
 public:
  PyLiteralReader(std::string text, std::string path) : text_(std::move(text)), path_(std::move(path)) {}

  PyValue document() {
    const PyValue root = value(0);
    skipBlanks();
    if (pos_ < text_.size()) fail("unexpected text after the model's closing '}'");
    if (root.kind != PyValue::Kind::Dict) failAt(root.line, "expected a { ... } dict (an mrcal .cameramodel)");
    return root;
  }

  [[noreturn]] void failAt(int line, const std::string& message) const {
    throw support::YamlError(path_ + ":" + std::to_string(line) + ": " + message);
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { failAt(line_, message); }

  void skipBlanks() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_;
        ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r') {
        ++pos_;
      } else if (c == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        return;
      }
    }
  }

  char peek() {
    skipBlanks();
    if (pos_ >= text_.size()) fail("unexpected end of file");
    return text_[pos_];
  }

  PyValue value(int depth) {
    if (depth > 16) fail("nested too deeply");
    const char c = peek();
    PyValue out;
    out.line = line_;
    if (c == '{') return container(depth, '}', true);
    if (c == '[' || c == '(') return container(depth, c == '[' ? ']' : ')', false);
    if (c == '\'' || c == '"' ||
        ((c == 'b' || c == 'r') && pos_ + 1 < text_.size() && (text_[pos_ + 1] == '\'' || text_[pos_ + 1] == '"'))) {
      if (c == 'b' || c == 'r') ++pos_;
      out.kind = PyValue::Kind::String;
      out.text = string();
      return out;
    }
    const std::size_t begin = pos_;
    while (pos_ < text_.size() && std::string(",]})\n\r\t #:").find(text_[pos_]) == std::string::npos) ++pos_;
    const std::string token = text_.substr(begin, pos_ - begin);
    if (token.empty()) fail(std::string("unexpected '") + c + "'");
    if (token == "True" || token == "False" || token == "None") {
      out.text = token;
      return out;
    }
    errno = 0;
    char* end = nullptr;
    out.number = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size() || errno == ERANGE || !std::isfinite(out.number))
      fail("'" + token + "' is not a number");
    out.kind = PyValue::Kind::Number;
    return out;
  }

  std::string string() {
    const char quote = text_[pos_++];
    std::string out;
    while (pos_ < text_.size() && text_[pos_] != quote) {
      if (text_[pos_] == '\n') fail("string not closed on its line");
      if (text_[pos_] == '\\' && pos_ + 1 < text_.size()) ++pos_;
      out += text_[pos_++];
    }
    if (pos_ >= text_.size()) fail("string not closed");
    ++pos_;
    return out;
  }

  PyValue container(int depth, char close, bool dict) {
    PyValue out;
    out.kind = dict ? PyValue::Kind::Dict : PyValue::Kind::List;
    out.line = line_;
    ++pos_;
    while (peek() != close) {
      if (dict) {
        const int key_line = line_;
        const PyValue key = value(depth + 1);
        if (key.kind != PyValue::Kind::String) failAt(key_line, "a key must be a quoted string");
        if (peek() != ':') fail("expected ':' after '" + key.text + "'");
        ++pos_;
        for (const auto& entry : out.entries)
          if (entry.first == key.text) failAt(key_line, "key '" + key.text + "' appears twice");
        out.entries.emplace_back(key.text, value(depth + 1));
      } else {
        out.items.push_back(value(depth + 1));
      }
      const char next = peek();
      if (next == ',') {
        ++pos_;
      } else if (next != close) {
        fail(std::string("expected ',' or '") + close + "'");
      }
    }
    ++pos_;
    return out;
  }

  std::string text_;
  std::string path_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

const PyValue* find(const PyValue& dict, const std::string& key) {
  for (const auto& entry : dict.entries)
    if (entry.first == key) return &entry.second;
  return nullptr;
}

std::vector<double> numbers(const PyLiteralReader& reader, const PyValue& list, const std::string& key) {
  if (list.kind != PyValue::Kind::List) reader.failAt(list.line, "key '" + key + "': expected a list of numbers");
  std::vector<double> out;
  for (const auto& item : list.items) {
    if (item.kind != PyValue::Kind::Number) reader.failAt(item.line, "key '" + key + "': expected numbers only");
    out.push_back(item.number);
  }
  return out;
}

// LENSMODEL_PINHOLE → 0, LENSMODEL_OPENCV<N> → N; anything else is refused by name.
int openCvCountOf(const PyLiteralReader& reader, const PyValue& lensmodel) {
  if (lensmodel.kind != PyValue::Kind::String) reader.failAt(lensmodel.line, "key 'lensmodel': expected a string");
  const std::string& name = lensmodel.text;
  if (name == "LENSMODEL_PINHOLE") return 0;
  for (const int count : {4, 5, 8, 12})
    if (name == "LENSMODEL_OPENCV" + std::to_string(count)) return count;
  reader.failAt(lensmodel.line, "lens model '" + name +
                                    "' is not one mire has (it reads LENSMODEL_PINHOLE and LENSMODEL_OPENCV4, 5, 8, "
                                    "12); convert it with mrcal-convert-lensmodel to one of those");
}

// mire's own keys: the covariance in the parameters' order, the camera's name, its RMS.
void readMireKeys(const PyLiteralReader& reader, const PyValue& root, Camera* camera) {
  if (const PyValue* name = find(root, "mire_camera_name")) {
    if (name->kind != PyValue::Kind::String) reader.failAt(name->line, "key 'mire_camera_name': expected a string");
    camera->name = name->text;
  }
  if (const PyValue* rms = find(root, "mire_rms_px")) {
    if (rms->kind != PyValue::Kind::Number || !(rms->number >= 0.0))
      reader.failAt(rms->line, "key 'mire_rms_px': expected a number >= 0");
    camera->rms_px = rms->number;
  }
  const PyValue* covariance = find(root, "mire_covariance");
  if (!covariance) return;
  const auto n = static_cast<Eigen::Index>(camera->params.size());
  if (covariance->kind != PyValue::Kind::List || static_cast<Eigen::Index>(covariance->items.size()) != n)
    reader.failAt(covariance->line,
                  "key 'mire_covariance': expected " + std::to_string(n) + " rows (one per intrinsic)");
  camera->covariance.resize(n, n);
  for (Eigen::Index r = 0; r < n; ++r) {
    const std::vector<double> row = numbers(reader, covariance->items[static_cast<std::size_t>(r)], "mire_covariance");
    if (static_cast<Eigen::Index>(row.size()) != n)
      reader.failAt(covariance->items[static_cast<std::size_t>(r)].line,
                    "key 'mire_covariance': expected " + std::to_string(n) + " values per row");
    for (Eigen::Index c = 0; c < n; ++c) camera->covariance(r, c) = row[static_cast<std::size_t>(c)];
    if (camera->covariance(r, r) < 0.0)
      reader.failAt(covariance->items[static_cast<std::size_t>(r)].line, "key 'mire_covariance': negative variance");
  }
}

std::string numberList(const std::vector<double>& values) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) text += (i ? ", " : "") + support::formatYamlNumber(values[i]);
  return text + "]";
}

// A Python string literal.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\\' || c == '\'') out += '\\';
    out += c;
  }
  return out + "'";
}

}  // namespace

Camera readCameraMrcal(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open for reading");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  PyLiteralReader reader(std::move(text), path.string());
  const PyValue root = reader.document();
  const auto required = [&](const std::string& key) -> const PyValue& {
    const PyValue* found = find(root, key);
    if (!found) reader.failAt(root.line, "missing key '" + key + "' (an mrcal .cameramodel has it)");
    return *found;
  };
  const int count = openCvCountOf(reader, required("lensmodel"));
  const PyValue& intrinsics_node = required("intrinsics");
  const std::vector<double> intrinsics = numbers(reader, intrinsics_node, "intrinsics");
  if (static_cast<int>(intrinsics.size()) != kIntrinsicCount + count)
    reader.failAt(intrinsics_node.line, "key 'intrinsics': " + std::to_string(intrinsics.size()) +
                                            " values, the lens model has " + std::to_string(kIntrinsicCount + count) +
                                            " (fx fy cx cy and " + std::to_string(count) + " coefficients)");
  const PyValue& size_node = required("imagersize");
  const std::vector<double> size = numbers(reader, size_node, "imagersize");
  if (size.size() != 2 || size[0] != std::floor(size[0]) || size[1] != std::floor(size[1]) || size[0] < 1 ||
      size[1] < 1 || size[0] > 100000 || size[1] > 100000)
    reader.failAt(size_node.line, "key 'imagersize': expected [width, height], integers in 1..100000");
  Camera camera;
  camera.width = static_cast<int>(size[0]);
  camera.height = static_cast<int>(size[1]);
  camera.lens = LensModel::OpenCV;
  camera.params = intrinsics;
  readMireKeys(reader, root, &camera);
  try {
    camera.validate();
  } catch (const std::invalid_argument& error) {
    reader.failAt(intrinsics_node.line, std::string("key 'intrinsics': ") + error.what());
  }
  return camera;
}

std::string cameraMrcalString(const Camera& camera) {
  camera.validate();
  if (camera.lens == LensModel::Fisheye)
    throw std::invalid_argument("mrcal has no equidistant (OpenCV fisheye) model: write ros or kalibr");
  const int count = camera.distortionCount();
  const std::string lensmodel = count == 0 ? "LENSMODEL_PINHOLE" : "LENSMODEL_OPENCV" + std::to_string(count);
  std::ostringstream out;
  // mrcal's pixel convention is OpenCV's (integer coordinates at pixel centres): no shift.
  out << "# mrcal camera model written by mire (doc/file-formats.md); read it with mrcal.cameramodel(path).\n"
      << "{\n"
      << "    'lensmodel': '" << lensmodel << "',\n"
      << "    # intrinsics are fx,fy,cx,cy,distortion0,distortion1,....\n"
      << "    'intrinsics': " << numberList(camera.params) << ",\n"
      << "    # extrinsics are rt_fromref: the camera at the reference\n"
      << "    'extrinsics': [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],\n"
      << "    'imagersize': [" << camera.width << ", " << camera.height << "],\n";
  if (!camera.name.empty() || camera.covariance.size() != 0 || camera.rms_px > 0.0)
    out << "    # mire's keys (mrcal ignores them): the camera's name, reprojection RMS (px) and the covariance\n"
        << "    # of the intrinsics in their order above\n";
  if (!camera.name.empty()) out << "    'mire_camera_name': " << quoted(camera.name) << ",\n";
  if (camera.rms_px > 0.0) out << "    'mire_rms_px': " << support::formatYamlNumber(camera.rms_px) << ",\n";
  if (camera.covariance.size() != 0) {
    out << "    'mire_covariance': [\n";
    for (Eigen::Index r = 0; r < camera.covariance.rows(); ++r) {
      std::vector<double> row(static_cast<std::size_t>(camera.covariance.cols()));
      for (Eigen::Index c = 0; c < camera.covariance.cols(); ++c)
        row[static_cast<std::size_t>(c)] = camera.covariance(r, c);
      out << "        " << numberList(row) << ",\n";
    }
    out << "    ],\n";
  }
  out << "}\n";
  return out.str();
}

}  // namespace mire::calibration
