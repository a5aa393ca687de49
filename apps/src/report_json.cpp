// Helpers of report.json (see report_json.hpp, doc/report-json.md).
#include "report_json.hpp"

#include "commands.hpp"

#include "mire/support/atomic_file.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace mire::app {
namespace {

void requireFinite(double value, const std::string& where) {
  if (!std::isfinite(value)) throw std::logic_error("report.json: non-finite number at " + where);
}

// Every number of the document is finite (nlohmann would silently write NaN as null).
void checkFinite(const Json& node, const std::string& where) {
  if (node.is_number_float()) requireFinite(node.get<double>(), where);
  if (node.is_object())
    for (const auto& item : node.items()) checkFinite(item.value(), where + "/" + item.key());
  if (node.is_array())
    for (std::size_t i = 0; i < node.size(); ++i) checkFinite(node[i], where + "/" + std::to_string(i));
}

}  // namespace

std::vector<std::string> commandLineOf(const CLI::App& command) {
  std::vector<std::string> words{"mire", command.get_name()};
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() == 0) continue;
    words.push_back(option->get_name());
    if (option->get_expected_max() == 0) continue;  // a flag
    for (const std::string& value : option->results()) words.push_back(value);
  }
  return words;
}

Json reportHeader(const std::string& report, const ReportProvenance& provenance) {
  Json header;
  header["format"] = "mire report.json 1";
  header["report"] = report;
  const auto paths = [](const std::vector<PathArgument>& arguments) {
    Json list = Json::array();
    for (const PathArgument& argument : arguments)
      list.push_back({{"role", argument.option}, {"path", argument.path.string()}});
    return list;
  };
  header["provenance"] = {{"mire_version", versionString()},
                          {"command_line", provenance.command_line},
                          {"inputs", paths(provenance.inputs)},
                          {"outputs", paths(provenance.outputs)}};
  return header;
}

void setNumber(Json& object, const std::string& key, double value, const std::string& reason) {
  if (std::isfinite(value)) {
    object[key] = value;
    return;
  }
  object[key] = nullptr;
  object[key + "_null_reason"] = reason;
}

Json numberArray(const Eigen::VectorXd& values) {
  Json array = Json::array();
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    requireFinite(values[i], "entry " + std::to_string(i));
    array.push_back(values[i]);
  }
  return array;
}

Json numberArray(const std::vector<double>& values) {
  return numberArray(
      Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()))));
}

Json matrixJson(const Eigen::MatrixXd& matrix) {
  Json rows = Json::array();
  for (Eigen::Index r = 0; r < matrix.rows(); ++r)
    rows.push_back(numberArray(Eigen::VectorXd(matrix.row(r).transpose())));
  return rows;
}

Json covarianceJson(const std::vector<std::string>& names, const std::vector<std::string>& units,
                    const Eigen::MatrixXd& covariance) {
  if (covariance.rows() != static_cast<Eigen::Index>(names.size()) || covariance.cols() != covariance.rows())
    throw std::logic_error("report.json: a covariance of " + std::to_string(covariance.rows()) + "x" +
                           std::to_string(covariance.cols()) + " for " + std::to_string(names.size()) + " names");
  Eigen::MatrixXd symmetric = 0.5 * (covariance + covariance.transpose());
  symmetric.diagonal() = covariance.diagonal();
  return {{"names", names}, {"units", units}, {"matrix", matrixJson(symmetric)}};
}

void writeReportJson(const std::filesystem::path& path, const Json& document) {
  checkFinite(document, "");
  // Invalid UTF-8 in a user's file name is replaced (U+FFFD), not an exception.
  support::writeFileAtomically(path, document.dump(2, ' ', false, Json::error_handler_t::replace) + "\n");
}

}  // namespace mire::app
