// The legs measured in rendered images (doc/legs.md "Measuring a leg";
// doc/studies/2026-11-27-legs-measured.md): campaigns of `mire simulate campaign --legs` (the true
// robot exactly of its model, few images per pose), every leg's axis measured as `mire measure
// --legs` does, against the true axes: error/σ of the 4 δ components; then, for the hexapod, the
// identification from the legs alone: the base joints in the camera frame against the truth, in σ.
// Usage: bench_legs_images [campaigns = 20] [mechanism = gough-stewart] [images per pose = 3]
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/legs_csv.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/identify_legs.hpp"
#include "mire/pipeline/leg_measurement.hpp"
#include "sample_statistics.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace mire;

struct Totals {
  std::array<std::vector<double>, 4> z;      // error/σ per δ component
  std::array<std::vector<double>, 4> sigma;  // σ per component (mrad, mm)
  std::array<std::vector<double>, 4> error;  // error per component (mrad, mm)
  std::vector<double> spread_ratio, base_z, base_sigma_mm;
  int legs_expected = 0, legs_measured = 0;
  double largest_base_error_mm = 0.0;
};

void compareLegs(const std::vector<pipeline::PoseLegs>& poses, const fs::path& truth_csv, int leg_count, Totals& t) {
  std::map<std::pair<std::string, int>, support::Line3d> truth;
  for (const mechanism::LegObservation& o : mechanism::readLegsCsv(truth_csv, leg_count))
    truth[{o.pose_id, o.leg}] = o.line;
  t.legs_expected += static_cast<int>(truth.size());
  for (const pipeline::PoseLegs& pose : poses) {
    for (const std::string& problem : pose.problems)
      std::printf("  pose %s: %s\n", pose.pose_id.c_str(), problem.c_str());
    t.spread_ratio.insert(t.spread_ratio.end(), pose.spread_ratios.begin(), pose.spread_ratios.end());
    for (const mechanism::LegObservation& leg : pose.legs) {
      ++t.legs_measured;
      const Eigen::Vector4d error = support::lineDifference(truth.at({leg.pose_id, leg.leg}), leg.line);
      const Eigen::Vector4d z = leg.covariance.llt().matrixL().solve(error);
      for (int k = 0; k < 4; ++k) {
        t.z[k].push_back(z[k]);
        t.sigma[k].push_back(1e3 * std::sqrt(leg.covariance(k, k)));
        t.error[k].push_back(1e3 * error[k]);
      }
    }
  }
}

// Legs only: the base joints cTb·b_i (which no gauge moves) against the truth, in σ.
void legsOnlyBaseJoints(const datasets::MechanismImageCampaign& campaign, const std::vector<mechanism::JointRow>& joints,
                        const std::vector<mechanism::LegObservation>& legs, Totals& t) {
  std::vector<mechanism::PoseObservation> poses;
  for (const mechanism::JointRow& row : joints) {
    mechanism::PoseObservation p;
    p.id = row.pose_id;
    p.joints = row.joints;
    poses.push_back(p);
  }
  const pipeline::LegIdentification run =
      pipeline::identifyWithLegs(pipeline::chooseModel("gough-stewart", ""), poses, legs, mechanism::Observations::Legs);
  const mechanism::LegIdentificationResult& r = run.result;
  std::printf("  legs only: chi2/dof %.3f, %s\n", r.chi2 / std::max(1, r.dof),
              r.converged ? "converged" : "NOT converged");
  const Eigen::Isometry3d cTb = r.model.external.baseFromCamera(r.model.externalValues()).inverse();
  const Eigen::Isometry3d cTb_true = campaign.bTc.inverse();
  for (int i = 0; i < 6; ++i) {
    const std::string n = std::to_string(i + 1);
    const auto value = [&](const mechanism::ParameterSet& set, const std::string& axis) { return set.value(axis + n); };
    const Eigen::Vector3d b(value(r.model.parameters, "bx"), value(r.model.parameters, "by"),
                            value(r.model.parameters, "bz"));
    const Eigen::Vector3d truth(value(campaign.robot.geometry, "bx"), value(campaign.robot.geometry, "by"),
                                value(campaign.robot.geometry, "bz"));
    const auto at = [&](const std::string& name) {
      return static_cast<Eigen::Index>(std::find(r.free_names.begin(), r.free_names.end(), name) - r.free_names.begin());
    };
    const Eigen::Index k[3] = {at("bx" + n), at("by" + n), at("bz" + n)};
    Eigen::Matrix3d cov;
    for (int u = 0; u < 3; ++u)
      for (int v = 0; v < 3; ++v) cov(u, v) = r.covariance(k[u], k[v]);
    const Eigen::Matrix3d cov_c = cTb.linear() * cov * cTb.linear().transpose();
    const Eigen::Vector3d error = cTb * b - cTb_true * truth;
    for (int u = 0; u < 3; ++u) {
      t.base_z.push_back(error[u] / std::sqrt(cov_c(u, u)));
      t.base_sigma_mm.push_back(1e3 * std::sqrt(cov_c(u, u)));
    }
    t.largest_base_error_mm = std::max(t.largest_base_error_mm, 1e3 * error.norm());
  }
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

int beyond(const std::vector<double>& z, double limit) {
  return static_cast<int>(std::count_if(z.begin(), z.end(), [&](double x) { return std::abs(x) > limit; }));
}

}  // namespace

int main(int argc, char** argv) {
  const int campaigns = argc > 1 ? std::atoi(argv[1]) : 20;
  const std::string mechanism_name = argc > 2 ? argv[2] : "gough-stewart";
  const int images = argc > 3 ? std::atoi(argv[3]) : 3;
  const fs::path root = fs::temp_directory_path() / "mire-bench-legs-images";
  Totals t;
  for (int c = 0; c < campaigns; ++c) {
    datasets::MechanismImageCampaignSpec spec = datasets::MechanismImageCampaignSpec::reference(mechanism_name);
    spec.seed = 7000 + static_cast<std::uint64_t>(c);
    spec.images_per_pose = images;
    spec.calibration_views = 3;
    spec.unmodelled_defects = false;
    spec.leg_radius_m = 0.008;
    const fs::path dir = root / std::to_string(c);
    const datasets::MechanismImageCampaign campaign = datasets::generateMechanismImageCampaign(spec, dir);
    const pipeline::LegsSpec legs_spec = pipeline::readLegsYaml(campaign.legs_file());
    const mechanism::RegisteredModel model = pipeline::chooseModel(legs_spec.model, "").registered();
    const auto joints = mechanism::readJointsCsv(campaign.joints_file(), model.mechanism->jointColumnNames());
    const auto poses = pipeline::measureLegFolders(campaign.camera, legs_spec, joints, campaign.pose_images(), 0,
                                                   c == 0 ? dir : fs::path());
    std::printf("campaign %d (seed %llu): %zu poses\n", c, static_cast<unsigned long long>(spec.seed), poses.size());
    compareLegs(poses, dir / "truth" / "legs.csv", model.mechanism->legCount(), t);
    std::vector<mechanism::LegObservation> legs;
    for (const auto& pose : poses) legs.insert(legs.end(), pose.legs.begin(), pose.legs.end());
    if (mechanism_name == "gough-stewart") legsOnlyBaseJoints(campaign, joints, legs, t);
    if (c > 0) fs::remove_all(dir);
  }
  const char* names[4] = {"a1 [mrad]", "a2 [mrad]", "b1 [mm]", "b2 [mm]"};
  std::printf("\n%s, %d campaigns x %d images per pose: %d of %d legs measured\n", mechanism_name.c_str(), campaigns,
              images, t.legs_measured, t.legs_expected);
  std::printf("%-10s %12s %12s %12s %10s %10s\n", "component", "std(err/s)", "mean(err/s)", "median sigma", "rms error",
              "beyond 3s");
  for (int k = 0; k < 4; ++k) {
    double mean = 0.0, rms = 0.0;
    for (double z : t.z[k]) mean += z / static_cast<double>(t.z[k].size());
    for (double e : t.error[k]) rms += e * e / static_cast<double>(t.error[k].size());
    std::printf("%-10s %12.3f %12.3f %12.5f %10.5f %10d\n", names[k], test::sampleStandardDeviation(t.z[k]), mean,
                median(t.sigma[k]), std::sqrt(rms), beyond(t.z[k], 3.0));
  }
  std::printf("median spread ratio of the images against the fits: %.3f\n", median(t.spread_ratio));
  if (!t.base_z.empty())
    std::printf(
        "legs only, base joints in the camera frame: std(error/sigma) %.3f over %zu coordinates, beyond 3 "
        "sigma %d, median sigma %.4f mm, largest error %.3f mm\n",
        test::sampleStandardDeviation(t.base_z), t.base_z.size(), beyond(t.base_z, 3.0), median(t.base_sigma_mm),
        t.largest_base_error_mm);
  std::printf("first campaign's contour drawings: %s/*.png\n", (root / "0").string().c_str());
  return 0;
}
