// A model's nominal geometry from a parameter file (identify.hpp, applyNominalFile).
#include "mire/datasets/data_dir.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/pipeline/identify.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace mire::pipeline {
namespace mech = mire::mechanism;

namespace {

// Keys a parameter file may carry besides the model's geometry (an identified file's mounting).
std::vector<std::string> mountingKeys() {
  std::vector<std::string> keys{"amplification"};
  for (auto form : {mech::ExternalForm::AxisAligned, mech::ExternalForm::Full, mech::ExternalForm::CameraFrame,
                    mech::ExternalForm::CameraOnEffector})
    for (const auto& n : mech::ExternalParameterization(form).parameters().names()) keys.push_back(n);
  return keys;
}

mech::H4Nominal h4NominalFrom(const mech::ParameterSet& g, const mech::ParameterFile& file) {
  mech::H4Nominal n;
  n.R = g.value("R");
  n.L = g.value("L");
  n.l = g.value("l");
  n.h = g.value("h");
  n.d = g.value("d");
  for (int i = 0; i < 4; ++i) {
    n.alpha[static_cast<std::size_t>(i)] = g.value("alpha" + std::to_string(i + 1));
    n.q0[static_cast<std::size_t>(i)] = g.value("q0" + std::to_string(i + 1));
  }
  if (const auto* entry = file.find("amplification")) n.amplification = file.number(*entry);
  return n;
}

// The H4 models start from model 12's values (the family's first model): `h4_nominal.yaml`.
std::string h4KeyModel(const mech::ModelInfo& info) { return mech::mechanismFamily(info.family).models.front(); }

// The parameters a nominal file for `chosen` may give: its own, or model 12's for an H4 model.
// A file written for another model (its `model:` key) is refused before its keys are compared.
bool givesModel12Keys(const mech::ParameterFile& file, const std::string& chosen) {
  const mech::ModelInfo info = mech::modelInfo(chosen);
  const mech::ParameterFileEntry* entry = file.find("model");
  // A described model's identified file names its own copy of the description.
  if (entry && mech::isDescriptionFile(chosen) && mech::isDescriptionFile(entry->text)) return false;
  const std::string file_model = entry ? entry->text : info.h4_nominal ? h4KeyModel(info) : chosen;
  if (file_model == chosen && info.h4_nominal && file_model != h4KeyModel(info) && !info.variants.empty())
    throw std::runtime_error(file.where(*entry) + ": --model " + chosen + " is identified through its variants (" +
                             info.variants + "), which start from " + h4KeyModel(info) + "'s values: give a " +
                             h4KeyModel(info) + " parameter file (datasets/specs/h4_nominal.yaml)");
  if (file_model == chosen) return info.h4_nominal && file_model == h4KeyModel(info);
  if (info.h4_nominal && file_model == h4KeyModel(info)) return true;
  throw std::runtime_error(file.where(*entry) + ": a '" + file_model + "' parameter file, not a nominal for --model " +
                           chosen + " (it takes " + chosen + "'s own parameters" +
                           (info.h4_nominal ? " or " + h4KeyModel(info) + "'s" : std::string()) + ")");
}

}  // namespace

void applyNominalFile(ModelChoice& choice, const std::filesystem::path& path) {
  const mech::ParameterFile file = mech::readParameterFile(path);
  if (givesModel12Keys(file, choice.model)) {
    mech::ParameterSet model12 = mech::h4Model12Parameters(mech::H4Nominal{});
    mech::applyParameterFile(file, model12, mountingKeys());
    choice.h4 = h4NominalFrom(model12, file);
    return;
  }
  mech::ParameterSet nominal = mech::makeRegisteredModel(choice.model, choice.h4).nominal;
  mech::applyParameterFile(file, nominal, mountingKeys());
  choice.nominal = std::move(nominal);
}

void applyNominal(ModelChoice& choice, const std::string& file) {
  if (!file.empty())
    applyNominalFile(choice, file);
  else if (mech::modelInfo(choice.model).h4_nominal)
    applyNominalFile(choice, datasets::specPath("h4_nominal.yaml"));
}

}  // namespace mire::pipeline
