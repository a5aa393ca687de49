// Honesty of the identification σ at the pose level (run by hand; doc/uncertainty.md):
//  1. exact-model robots (model 12 represents them exactly): over N simulated campaigns,
//     std(error/σ) of every identified parameter (target [0.8, 1.25]);
//  2. a robot with defects model 12 cannot represent (the demo's error sizes): printed σ against
//     the spread over repeated campaigns and over 100 random 71-pose subsets (target [0.5, 2]),
//     the outlier list, and the outlier list with two corrupted poses injected.
// Usage: bench_identify_sigma [campaigns=40] [same|different robots]
#include "mire/datasets/h4_true_robot.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/identification_covariance.hpp"
#include "mire/mechanism/variants.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace mire;
namespace mech = mire::mechanism;

datasets::H4ErrorSizes demoSizes(bool defects) {
  datasets::H4ErrorSizes sizes = datasets::MechanismImageCampaignSpec::reference("h4").h4_errors;
  if (!defects) sizes.leg_length_m = sizes.pivot_height_m = sizes.axis_tilt_rad = sizes.bar_mismatch_m = 0.0;
  return sizes;
}

struct Campaign {
  std::vector<mech::PoseObservation> poses;
  Eigen::VectorXd truth_geometric;  // model-12 values of the true robot (best description)
  Eigen::Isometry3d bTc, mTe;
};

Campaign simulate(std::uint64_t robot_seed, std::uint64_t noise_seed, bool defects) {
  const auto sizes = demoSizes(defects);
  const datasets::H4TrueKinematics robot(datasets::makeTrueGeometry({}, sizes, robot_seed));
  datasets::H4MeasurementNoise noise;
  noise.encoder_rad = 2e-5;
  Campaign c;
  c.poses = datasets::toObservations(
      datasets::simulateMeasurements(robot, datasets::protocolPoses(), noise, noise_seed), noise);
  c.truth_geometric = mech::h4Model12Parameters(datasets::drawModel12Values({}, sizes, robot_seed)).values();
  c.bTc = robot.baseTCamera();
  c.mTe = robot.markerTEffector();
  return c;
}

// error/σ per free parameter (z_BC is compared in the z_ME gauge of the model: only
// z_BC + z_ME is identifiable, paper eq. 24).
std::map<std::string, double> normalisedErrors(const mech::IdentificationResult& r, const Campaign& c,
                                               const Eigen::MatrixXd* covariance = nullptr) {
  const int G = r.model.geometricCount();
  Eigen::VectorXd truth(r.model.parameters.size());
  truth << c.truth_geometric, r.model.external.valuesFrom(c.bTc, c.mTe);
  const auto& p = r.model.parameters;
  const double z_me_true = truth[static_cast<Eigen::Index>(p.index("z_ME"))];
  truth[static_cast<Eigen::Index>(p.index("z_BC"))] += z_me_true - p.value("z_ME");
  std::map<std::string, double> out;
  for (const auto& name : r.free_names) {
    const auto i = static_cast<Eigen::Index>(p.index(name));
    const auto f =
        static_cast<Eigen::Index>(std::find(r.free_names.begin(), r.free_names.end(), name) - r.free_names.begin());
    const double sigma = covariance ? std::sqrt((*covariance)(f, f)) : r.sigma[i];
    out[name] = (p[static_cast<std::size_t>(i)].value - truth[i]) / sigma;
  }
  (void)G;
  return out;
}

// Over campaigns: RMS of error/σ per parameter for the printed σ, the σ without the axis
// alignment term, and the sandwich σ.
struct Coverage {
  std::map<std::string, std::vector<double>> printed, no_alignment, sandwich;
  std::vector<std::string> names;
  double chi2_sum = 0.0;
  int runs = 0, failed = 0;
  void add(const mech::IdentificationResult& r, const std::vector<mech::PoseObservation>& poses, const Campaign& c) {
    names = r.free_names;
    chi2_sum += r.chi2 / r.dof;
    ++runs;
    const Eigen::MatrixXd bare = r.covariance - r.termCovariance(mech::CovarianceTerm::kAlignment);
    const Eigen::MatrixXd robust =
        mech::sandwichCovariance(r, poses) + r.termCovariance(mech::CovarianceTerm::kAlignment);
    for (const auto& [name, value] : normalisedErrors(r, c)) printed[name].push_back(value);
    for (const auto& [name, value] : normalisedErrors(r, c, &bare)) no_alignment[name].push_back(value);
    for (const auto& [name, value] : normalisedErrors(r, c, &robust)) sandwich[name].push_back(value);
  }
  static double rms(const std::vector<double>& v) {
    double sq = 0.0;
    for (double x : v) sq += x * x;
    return std::sqrt(sq / static_cast<double>(v.size()));
  }
  void print() const {
    std::printf("   %d campaigns (%d failed to initialise), mean chi2/dof %.3f\n", runs, failed, chi2_sum / runs);
    std::printf("   parameter  RMS(error/sigma): printed   without alignment term   sandwich\n");
    double lo = 1e9, hi = 0.0;
    for (const auto& name : names) {
      const double value = rms(printed.at(name));
      lo = std::min(lo, value);
      hi = std::max(hi, value);
      std::printf("   %-8s   %8.3f   %8.3f   %8.3f\n", name.c_str(), value, rms(no_alignment.at(name)),
                  rms(sandwich.at(name)));
    }
    std::printf("   printed sigma: range over parameters [%.3f, %.3f]\n", lo, hi);
  }
};

void coverageStudy(int campaigns, bool same_robot, bool defects) {
  std::printf("%s robot (%s), %d campaigns, variant D\n", defects ? "2. unmodelled-defect" : "1. exact-model",
              same_robot ? "same robot" : "different robots", campaigns);
  Coverage coverage;
  for (int k = 0; k < campaigns; ++k) {
    const Campaign c = simulate(same_robot ? 2004 : 2004 + static_cast<std::uint64_t>(k),
                                1000 + static_cast<std::uint64_t>(k), defects);
    try {
      const auto r = mech::identifyH4Variant('D', {}, c.poses);
      coverage.add(r, c.poses, c);
    } catch (const std::exception&) {
      ++coverage.failed;
    }
  }
  coverage.print();
}

double spread(const std::vector<double>& v) {
  double mean = 0.0, sq = 0.0;
  for (double x : v) mean += x / static_cast<double>(v.size());
  for (double x : v) sq += (x - mean) * (x - mean);
  return std::sqrt(sq / static_cast<double>(v.size() - 1));
}

void defectStudy(int campaigns) {
  std::printf("\n3. robot with unmodelled defects (demo sizes, robot seed 2004)\n");
  const Campaign c0 = simulate(2004, 1, true);
  const auto full = mech::identifyH4Variant('D', {}, c0.poses);
  std::printf("   81 poses: chi2/dof %.2f, covariance: %s; outliers: %zu\n", full.chi2 / full.dof,
              full.covarianceMethod().c_str(), full.outliers.size());
  // Spread over random 71-pose subsets, and over repeated campaigns of the same robot.
  std::map<std::string, std::vector<double>> subsets, repeats;
  std::mt19937_64 rng(5);
  for (int k = 0; k < 100; ++k) {
    auto shuffled = c0.poses;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    shuffled.resize(71);
    mech::IdentificationOptions options;
    options.compute_identifiability = false;
    const auto r = mech::identifyH4Variant('D', {}, shuffled, options);
    for (const auto& name : r.free_names) subsets[name].push_back(r.model.parameters.value(name));
  }
  for (int k = 0; k < campaigns; ++k) {
    const Campaign c = simulate(2004, 500 + static_cast<std::uint64_t>(k), true);
    mech::IdentificationOptions options;
    options.compute_identifiability = false;
    const auto r = mech::identifyH4Variant('D', {}, c.poses, options);
    for (const auto& name : r.free_names) repeats[name].push_back(r.model.parameters.value(name));
  }
  // Subsets of 71 among 81 overlap: their spread is that of a delete-10 jackknife, whose
  // variance estimate of the 81-pose fit is (71/10) × spread².
  std::printf(
      "   parameter   sigma/spread(100 x 71-pose subsets)   sigma/jackknife   sigma/spread(%d campaigns, same robot)   "
      "|error|/sigma\n",
      campaigns);
  const auto z = normalisedErrors(full, c0);
  for (const auto& name : full.free_names) {
    const double sigma = full.sigmaOf(name);
    std::printf("   %-8s    %8.2f                              %8.2f    %8.2f                %6.2f\n", name.c_str(),
                sigma / spread(subsets[name]), sigma / (spread(subsets[name]) * std::sqrt(71.0 / 10.0)),
                sigma / spread(repeats[name]), std::abs(z.at(name)));
  }
  // Two corrupted poses: 3 mm and 0.3 deg off.
  auto corrupted = c0.poses;
  for (const std::size_t j : {std::size_t{17}, std::size_t{52}}) {
    corrupted[j].cTm[0] += 3e-3;
    corrupted[j].cTm[4] += 0.3 * datasets::kH4Degree;
  }
  for (const bool robust : {false, true}) {
    mech::IdentificationOptions options;
    if (robust) options.loss = mech::RobustLoss::Huber;
    const auto r = mech::identifyH4Variant('D', {}, corrupted, options);
    std::printf("   two corrupted poses (ids %s, %s)%s: outliers:", corrupted[17].id.c_str(), corrupted[52].id.c_str(),
                robust ? " --robust" : "");
    for (const auto& id : r.outliers) std::printf(" %s", id.c_str());
    std::printf("; chi2/dof %.2f\n", r.chi2 / r.dof);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int campaigns = argc > 1 ? std::atoi(argv[1]) : 40;
  const bool same = argc > 2 ? std::string(argv[2]) == "same" : false;
  coverageStudy(campaigns, same, false);
  coverageStudy(campaigns, same, true);
  defectStudy(campaigns);
  return 0;
}
