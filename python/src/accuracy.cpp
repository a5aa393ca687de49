// `mire accuracy` on arrays (doc/accuracy.md): the ISO 9283 figures of measured cycles, as dicts
// in SI units (m, rad), each with its σ and its noise-only part.
#include "bindings.hpp"

#include "mire/pipeline/accuracy.hpp"

#include <string>
#include <vector>

namespace mire::python {
namespace {

namespace mech = mechanism;
namespace pipe = pipeline;

py::dict noiseDict(const mech::NoiseOnly& n) {
  py::dict out;
  out["mean"] = n.mean;
  out["p95"] = n.p95;
  return out;
}

py::list noiseList(const std::array<mech::NoiseOnly, 3>& n) {
  py::list out;
  for (const auto& item : n) out.append(noiseDict(item));
  return out;
}

py::dict positionDict(const mech::PositionAccuracy& p) {
  py::dict out;
  out["position"] = p.position;
  out["cycles"] = p.cycles;
  out["commanded"] = Eigen::VectorXd(p.commanded);
  out["barycentre"] = Eigen::VectorXd(p.barycentre);
  out["ap_p"] = p.ap_p;
  out["ap_xyz"] = Eigen::VectorXd(p.ap_xyz);
  out["ap_abc"] = Eigen::VectorXd(p.ap_abc);
  out["sigma_ap_p"] = p.sigma_ap_p;
  out["sigma_ap_xyz"] = Eigen::VectorXd(p.sigma_ap_xyz);
  out["sigma_ap_abc"] = Eigen::VectorXd(p.sigma_ap_abc);
  out["noise_ap_p"] = noiseDict(p.noise_ap_p);
  out["noise_ap_abc"] = noiseList(p.noise_ap_abc);
  out["l_mean"] = p.l_mean;
  out["s_l"] = p.s_l;
  out["rp_l"] = p.rp_l;
  out["s_abc"] = Eigen::VectorXd(p.s_abc);
  out["rp_abc"] = Eigen::VectorXd(p.rp_abc);
  out["noise_rp_l"] = noiseDict(p.noise_rp_l);
  out["noise_rp_abc"] = noiseList(p.noise_rp_abc);
  out["warnings"] = p.warnings;
  return out;
}

py::dict distanceDict(const mech::DistanceAccuracy& d) {
  py::dict out;
  out["from"] = d.from;
  out["to"] = d.to;
  out["cycles"] = d.cycles;
  out["d_commanded"] = d.d_commanded;
  out["d_mean"] = d.d_mean;
  out["ad_p"] = d.ad_p;
  out["sigma_ad_p"] = d.sigma_ad_p;
  out["s_d"] = d.s_d;
  out["rd"] = d.rd;
  out["noise_ad_p"] = noiseDict(d.noise_ad_p);
  out["noise_rd"] = noiseDict(d.noise_rd);
  out["warnings"] = d.warnings;
  return out;
}

py::dict lineDict(const mech::LineStraightness& l) {
  py::dict out;
  out["line"] = l.line;
  out["points"] = l.points;
  out["rms"] = l.rms;
  out["max"] = l.max;
  out["rms_beyond_noise"] = l.rms_beyond_noise;
  out["noise_rms"] = noiseDict(l.noise_rms);
  out["noise_max"] = noiseDict(l.noise_max);
  out["warnings"] = l.warnings;
  return out;
}

// Measured poses: PoseRow (readPosesCsv) or PoseObservation (observationsFromArrays) items; an
// observation's "line" in messages is its index in the list (1-based).
std::vector<mech::PoseRow> measuredRows(const py::iterable& measured, const std::string& what) {
  std::vector<mech::PoseRow> rows;
  int index = 0;
  for (const py::handle item : measured) {
    ++index;
    if (py::isinstance<mech::PoseRow>(item))
      rows.push_back(item.cast<mech::PoseRow>());
    else if (py::isinstance<mech::PoseObservation>(item))
      rows.push_back({item.cast<mech::PoseObservation>(), index});
    else
      throw py::type_error(what + "[" + std::to_string(index - 1) + "]: expected a PoseObservation or PoseRow");
  }
  return rows;
}

py::dict accuracy(const mech::PredictionModel& model, const std::vector<std::string>& ids,
                  const std::vector<std::string>& positions, const Eigen::MatrixXd& commanded,
                  const py::iterable& measured, const py::object& lines, int noise_draws, unsigned seed) {
  const mech::Mechanism& m = *model.mechanism;
  const auto n = static_cast<Eigen::Index>(ids.size());
  if (positions.size() != ids.size() || commanded.rows() != n || commanded.cols() != m.poseDof())
    throw py::value_error("accuracy: ids (N), positions (N) and commanded (N, " + std::to_string(m.poseDof()) + ": " +
                          py::str(py::cast(m.poseComponentNames())).cast<std::string>() + ") must agree; got " +
                          std::to_string(ids.size()) + ", " + std::to_string(positions.size()) + ", (" +
                          std::to_string(commanded.rows()) + ", " + std::to_string(commanded.cols()) + ")");
  std::vector<pipe::CommandedPose> commands;
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    commands.push_back({ids[k], positions[k], m.poseToTransform(commanded.row(i).transpose())});
  }
  const std::vector<mech::PoseRow> rows = measuredRows(measured, "measured");
  std::vector<pipe::LinePose> line_poses;
  if (!lines.is_none())
    for (const auto& [key, poses] : lines.cast<py::dict>())
      for (const mech::PoseRow& row :
           measuredRows(poses.cast<py::iterable>(), "lines['" + py::str(key).cast<std::string>() + "']"))
        line_poses.push_back({py::str(key).cast<std::string>(), row});
  mech::AccuracyOptions options;
  options.noise_draws = noise_draws;
  options.seed = seed;
  pipe::AccuracyResult r;
  {
    py::gil_scoped_release release;
    r = pipe::evaluateAccuracy(model, commands, rows, "measured", line_poses, options);
  }
  py::dict out;
  py::list p, d, l;
  for (const auto& x : r.positions) p.append(positionDict(x));
  for (const auto& x : r.distances) d.append(distanceDict(x));
  for (const auto& x : r.lines) l.append(lineDict(x));
  out["positions"] = p;
  out["distances"] = d;
  out["lines"] = l;
  out["unmeasured"] = r.unmeasured;
  out["cycles_used"] = r.cycles_used;
  return out;
}

}  // namespace

void bindAccuracy(py::module_& m) {
  m.def("accuracy", &accuracy, py::arg("model"), py::arg("ids"), py::arg("positions"), py::arg("commanded"),
        py::arg("measured"), py::arg("lines") = py::none(), py::arg("noise_draws") = 2000, py::arg("seed") = 9283,
        "`mire accuracy` on arrays: commanded poses (N, poseDof) in the base frame with their ids and positions "
        "(cycle j of a position is its j-th row), the measured target poses (PoseObservation or PoseRow, by id) "
        "read through the model's mounting, optional straight-line records {line_id: [poses]}. Returns "
        "{'positions': [ISO 9283 §7.2 figures], 'distances': [§7.4], 'lines': [straightness], 'unmeasured', "
        "'cycles_used'} in m and rad, each figure with its sigma and noise-only part.");
}

}  // namespace mire::python
