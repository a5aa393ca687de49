// Variants A–H of the paper's Table 2 (doc/mechanisms.md).
#include "mire/mechanism/variants.hpp"

#include <cctype>
#include <stdexcept>

namespace mire::mechanism {

namespace {

const std::vector<std::string> kAllForearms{"l1", "l2", "l3", "l4"};

std::vector<std::string> join(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The model-12 variant used to initialise a model-31 variant (same a-priori information).
char preliminaryVariant(char letter) {
  switch (letter) {
    case 'E':
    case 'F':
      return 'A';
    case 'G':
      return 'C';
    default:
      return 'D';
  }
}

}  // namespace

const std::vector<H4Variant>& h4Variants() {
  static const std::vector<H4Variant> variants = [] {
    using K = H4ModelKind;
    using F = ExternalForm;
    std::vector<H4Variant> v;
    v.push_back({'A', K::Model12, F::AxisAligned, {"h", "l"}, {}, 10, 7, "model 12, h and l fixed"});
    v.push_back({'B', K::Model12, F::AxisAligned, {"h"}, {}, 11, 7, "model 12, h fixed"});
    v.push_back({'C', K::Model12, F::AxisAligned, {"l"}, {}, 11, 7, "model 12, l fixed"});
    v.push_back({'D', K::Model12, F::AxisAligned, {}, {}, 12, 7, "model 12"});
    v.push_back({'E',
                 K::Model31Camera,
                 F::CameraFrame,
                 join({"h"}, kAllForearms),
                 {{"L1", "L2", "L3", "L4"}},
                 25,
                 3,
                 "model 31 (camera frame), equal arm lengths, h and l fixed"});
    v.push_back({'F',
                 K::Model31Camera,
                 F::CameraFrame,
                 join({"h"}, kAllForearms),
                 {},
                 28,
                 3,
                 "model 31 (camera frame), h and l fixed"});
    v.push_back({'G', K::Model31Camera, F::CameraFrame, kAllForearms, {}, 29, 3, "model 31 (camera frame), l fixed"});
    v.push_back({'H', K::Model31Camera, F::CameraFrame, {}, {}, 33, 3, "model 31 (camera frame)"});
    return v;
  }();
  return variants;
}

const H4Variant& h4Variant(char letter) {
  const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(letter)));
  for (const H4Variant& v : h4Variants())
    if (v.letter == upper) return v;
  throw std::invalid_argument(std::string("unknown model variant '") + letter + "' (expected A-H)");
}

IdentificationModel makeH4VariantModel(char letter, const H4Nominal& nominal, const std::vector<PoseObservation>& poses,
                                       const IdentificationOptions& options) {
  const H4Variant& variant = h4Variant(letter);
  std::shared_ptr<const Mechanism> model12 = makeH4Mechanism(H4ModelKind::Model12, nominal);
  IdentificationModel initial = makeInitialModel(model12, h4Model12Parameters(nominal), poses, ExternalForm::AxisAligned);
  if (variant.model == H4ModelKind::Model12) {
    initial.parameters.fix(variant.fixed);
    return initial;
  }

  // Model 31 in the camera frame: start from the matching model-12 identification.
  const H4Variant& preliminary = h4Variant(preliminaryVariant(variant.letter));
  initial.parameters.fix(preliminary.fixed);
  IdentificationOptions preliminary_options;
  preliminary_options.use_pose_covariances = options.use_pose_covariances;
  preliminary_options.joint_sigma = options.joint_sigma;
  preliminary_options.loss = options.loss;
  preliminary_options.loss_scale = options.loss_scale;
  preliminary_options.compute_identifiability = false;
  const IdentificationResult first = identify(initial, poses, preliminary_options);
  const ParameterSet& p = first.model.parameters;

  ParameterSet geometric12;
  for (const std::string& name : model12->nominal().names()) geometric12.add(p.at(name));
  Eigen::Vector3d shift;
  const ParameterSet m31 = model31FromModel12(geometric12, &shift);
  // B' (axis-aligned camera) <- B12: b12Tb' = b12Tc · cTb' = [Rz(psi_BC), (x_BC, y_BC, z_BC)].
  Eigen::Isometry3d b12_T_aligned = Eigen::Isometry3d::Identity();
  b12_T_aligned.linear() = Eigen::AngleAxisd(p.value("psi_BC"), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  b12_T_aligned.translation() << p.value("x_BC"), p.value("y_BC"), p.value("z_BC");
  Eigen::Isometry3d b12_T_b31 = Eigen::Isometry3d::Identity();
  b12_T_b31.translation() = shift;
  ParameterSet camera31 = model31CameraFromModel31(m31, b12_T_aligned.inverse() * b12_T_b31);
  // A-priori (nominal) values for the parameters the variant fixes.
  for (const std::string& name : variant.fixed) camera31.setValue(name, name == "h" ? nominal.h : nominal.l);

  const ExternalParameterization external(ExternalForm::CameraFrame, first.model.external.alignment());
  ParameterSet external_values = external.parameters();
  for (const char* name : {"x_ME", "y_ME", "z_ME", "psi_ME"}) external_values.setValue(name, p.value(name));

  std::shared_ptr<const Mechanism> mechanism = makeH4Mechanism(H4ModelKind::Model31Camera, nominal);
  IdentificationModel model = makeIdentificationModel(mechanism, camera31, external, external_values);
  model.parameters.fix(variant.fixed);
  for (const auto& group : variant.tied) model.parameters.tie(group);
  return model;
}

IdentificationResult identifyH4Variant(char letter, const H4Nominal& nominal, const std::vector<PoseObservation>& poses,
                                       const IdentificationOptions& options) {
  return identify(makeH4VariantModel(letter, nominal, poses, options), poses, options);
}

}  // namespace mire::mechanism
